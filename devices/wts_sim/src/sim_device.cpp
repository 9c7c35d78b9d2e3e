#include "tactile_wts/sim_device.hpp"

#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>

namespace tactile {
namespace wts {

namespace {
long long steadyMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}
}  // namespace

SimulatedWts::~SimulatedWts() { stop(); }

uint32_t SimulatedWts::nowMs() const { return static_cast<uint32_t>(steadyMs() - t0_ms_); }

double SimulatedWts::uniform() {  // xorshift64*
  rng_ ^= rng_ >> 12;
  rng_ ^= rng_ << 25;
  rng_ ^= rng_ >> 27;
  return static_cast<double>((rng_ * 2685821657736338717ULL) >> 11) * (1.0 / 9007199254740992.0);
}

double SimulatedWts::gaussian() {
  const double u1 = 1.0 - uniform();  // (0, 1]: log() finite
  const double u2 = uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.14159265358979323846 * u2);
}

bool SimulatedWts::checkTaxelFaults(const std::vector<TaxelFault>& faults, std::string* why) const {
  for (std::size_t i = 0; i < faults.size(); ++i) {
    const TaxelFault& f = faults[i];
    const std::string where = "taxel_faults[" + std::to_string(i) + "]";
    if (f.row < 0 || f.row >= p_.cells.rows || f.col < 0 || f.col >= p_.cells.cols) {
      if (why)
        *why = where + ": taxel (" + std::to_string(f.row) + ", " + std::to_string(f.col) + ") is outside the " +
               std::to_string(p_.cells.rows) + " x " + std::to_string(p_.cells.cols) + " pad (row, col from 0)";
      return false;
    }
    if (f.kind == TaxelFaultKind::Stuck && !(f.value >= 0.0 && f.value <= p_.full_scale)) {
      if (why) *why = where + ": stuck value " + std::to_string(f.value) + " must be in [0, " +
                      std::to_string(p_.full_scale) + "] counts";
      return false;
    }
    if (f.kind == TaxelFaultKind::Noisy && !(f.value >= 0.0 && f.value <= 4096.0)) {
      if (why) *why = where + ": noise " + std::to_string(f.value) + " must be in [0, 4096] counts (1 sigma)";
      return false;
    }
  }
  return true;
}

bool SimulatedWts::openPty(std::string* why) {
  const int m = posix_openpt(O_RDWR | O_NOCTTY);
  if (m < 0 || grantpt(m) != 0 || unlockpt(m) != 0) {
    if (why) *why = std::string("posix_openpt/grantpt/unlockpt: ") + std::strerror(errno);
    if (m >= 0) ::close(m);
    return false;
  }
  char name[128];
  if (ptsname_r(m, name, sizeof(name)) != 0) {
    if (why) *why = std::string("ptsname_r: ") + std::strerror(errno);
    ::close(m);
    return false;
  }
  // Keep one slave fd open in raw mode: no echo before the driver configures
  // the port, and the master never sees EIO while no driver is attached.
  const int s = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (s < 0) {
    if (why) *why = std::string("open ") + name + ": " + std::strerror(errno);
    ::close(m);
    return false;
  }
  termios tio{};
  tcgetattr(s, &tio);
  cfmakeraw(&tio);
  tcsetattr(s, TCSANOW, &tio);
  fcntl(m, F_SETFL, fcntl(m, F_GETFL) | O_NONBLOCK);
  fcntl(m, F_SETFD, FD_CLOEXEC);
  if (!p_.link.empty()) {
    ::unlink(p_.link.c_str());
    if (::symlink(name, p_.link.c_str()) != 0) {
      if (why) *why = "symlink " + p_.link + ": " + std::strerror(errno);
      ::close(s);
      ::close(m);
      return false;
    }
  }
  std::lock_guard<std::mutex> lk(mu_);
  master_ = m;
  slave_keep_ = s;
  slave_name_ = name;
  return true;
}

void SimulatedWts::closePty() {
  std::lock_guard<std::mutex> lk(mu_);
  if (master_ >= 0) ::close(master_);
  if (slave_keep_ >= 0) ::close(slave_keep_);
  master_ = slave_keep_ = -1;
}

bool SimulatedWts::start(const Params& p, std::string* why) {
  stop();
  p_ = p;
  ConfigResult r = map_.configure(p.cells);
  if (!r) {
    if (why) *why = r.message();
    return false;
  }
  if (!checkTaxelFaults(p.taxel_faults, why)) return false;
  faults_ = p.faults;
  taxel_faults_ = p.taxel_faults;
  rng_ = p.faults.seed ? p.faults.seed : 1;
  t0_ms_ = steadyMs();
  if (!openPty(why)) return false;
  plugged_ = true;
  running_ = true;
  thread_ = std::thread([this] { run(); });
  return true;
}

void SimulatedWts::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
  closePty();
  plugged_ = false;
  streaming_ = false;
  if (!p_.link.empty()) ::unlink(p_.link.c_str());
}

std::string SimulatedWts::path() const {
  if (!p_.link.empty()) return p_.link;
  std::lock_guard<std::mutex> lk(mu_);
  return slave_name_;
}

void SimulatedWts::setSource(FrameSource src) {
  std::lock_guard<std::mutex> lk(mu_);
  source_ = std::move(src);
  recording_.clear();
}

void SimulatedWts::setRecording(std::vector<RawTactileFrame> frames) {
  std::lock_guard<std::mutex> lk(mu_);
  recording_ = std::move(frames);
  rec_index_ = 0;
  source_ = nullptr;
}

void SimulatedWts::setFaults(const SimFaults& f) {
  std::lock_guard<std::mutex> lk(mu_);
  faults_ = f;
  rng_ = f.seed ? f.seed : 1;
}

bool SimulatedWts::setTaxelFaults(const std::vector<TaxelFault>& faults, std::string* why) {
  if (!checkTaxelFaults(faults, why)) return false;
  std::lock_guard<std::mutex> lk(mu_);
  taxel_faults_ = faults;
  return true;
}

SimStats SimulatedWts::stats() const {
  std::lock_guard<std::mutex> lk(mu_);
  return stats_;
}

void SimulatedWts::unplug() {
  // The device disappears: master closed, the driver's slave fd hangs up.
  plugged_ = false;
  streaming_ = false;
  closePty();
  if (!p_.link.empty()) ::unlink(p_.link.c_str());
}

bool SimulatedWts::replug() {
  if (plugged_) return true;
  {
    std::lock_guard<std::mutex> lk(mu_);
    tare_.fill(0);
  }
  if (!openPty(nullptr)) return false;
  plugged_ = true;
  return true;
}

void SimulatedWts::sendPacket(std::vector<uint8_t>& pkt) {
  bool faulted = false, stall = false;
  int stall_ms = 0;
  std::vector<uint8_t> pre;
  {
    std::lock_guard<std::mutex> lk(mu_);  // faults_ and rng_ are shared with setFaults()
    const SimFaults& f = faults_;
    if (f.garbage > 0 && uniform() < f.garbage) {
      const int n = 1 + static_cast<int>(uniform() * 32);
      for (int i = 0; i < n; ++i) pre.push_back(static_cast<uint8_t>(uniform() * 256));
      faulted = true;
    }
    if (f.stall > 0 && uniform() < f.stall) {
      stall = true;
      stall_ms = f.stall_ms;
      faulted = true;
    }
    if (f.bit_flip > 0 && uniform() < f.bit_flip && !pkt.empty()) {
      const std::size_t i = static_cast<std::size_t>(uniform() * static_cast<double>(pkt.size())) % pkt.size();
      pkt[i] = static_cast<uint8_t>(pkt[i] ^ (1u << (static_cast<unsigned>(uniform() * 8) & 7u)));
      faulted = true;
    }
    if (f.drop_byte > 0 && uniform() < f.drop_byte && !pkt.empty()) {
      const std::size_t i = static_cast<std::size_t>(uniform() * static_cast<double>(pkt.size())) % pkt.size();
      pkt.erase(pkt.begin() + static_cast<std::ptrdiff_t>(i));
      faulted = true;
    }
    if (f.truncate > 0 && uniform() < f.truncate) {
      pkt.resize(static_cast<std::size_t>(uniform() * static_cast<double>(pkt.size())));
      faulted = true;
    }
    if (f.bad_crc > 0 && uniform() < f.bad_crc && pkt.size() >= 2) {
      pkt[pkt.size() - 1] ^= 0x5A;
      faulted = true;
    }
  }
  if (stall) std::this_thread::sleep_for(std::chrono::milliseconds(stall_ms));
  pre.insert(pre.end(), pkt.begin(), pkt.end());
  std::lock_guard<std::mutex> lk(mu_);
  if (faulted) ++stats_.faults;
  if (master_ < 0) return;
  std::size_t done = 0;
  for (int tries = 0; done < pre.size() && tries < 200; ++tries) {
    const ssize_t w = ::write(master_, pre.data() + done, pre.size() - done);
    if (w > 0) {
      done += static_cast<std::size_t>(w);
    } else if (w < 0 && errno != EAGAIN && errno != EINTR) {
      return;
    } else {
      pollfd pfd{master_, POLLOUT, 0};
      ::poll(&pfd, 1, 5);  // reader not keeping up: wait a little, then drop (overrun)
    }
  }
}

void SimulatedWts::reply(uint8_t id, StatusCode st, const uint8_t* data, std::size_t n) {
  std::vector<uint8_t> payload(2);
  putU16(payload.data(), static_cast<uint16_t>(st));
  if (data != nullptr) payload.insert(payload.end(), data, data + n);
  std::vector<uint8_t> pkt(payload.size() + kOverhead);
  pkt.resize(encodePacket(id, payload.data(), payload.size(), pkt.data(), pkt.size()));
  sendPacket(pkt);
}

void SimulatedWts::sendFrame(uint8_t id, bool with_status) {
  if (held_.load()) {  // a stalled stream: nothing goes out
    std::lock_guard<std::mutex> lk(mu_);
    ++stats_.held_frames;
    return;
  }
  RawTactileFrame f;
  f.rows = static_cast<uint16_t>(p_.cells.rows);
  f.cols = static_cast<uint16_t>(p_.cells.cols);
  const uint32_t t = nowMs();
  {
    std::lock_guard<std::mutex> lk(mu_);
    if (source_) {
      source_(t, f);
    } else if (!recording_.empty()) {
      f = recording_[rec_index_ % recording_.size()];
      ++rec_index_;
    }
  }
  const int n = map_.cells();
  std::array<uint16_t, kMaxTaxels> tare_copy;
  {
    std::lock_guard<std::mutex> lk(mu_);
    tare_copy = tare_;
  }
  std::vector<uint16_t> dev(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const uint16_t v = f.counts[map_.toSensing(k)];
    const uint16_t tare = tare_copy[static_cast<std::size_t>(k)];
    uint16_t c = v > tare ? static_cast<uint16_t>(v - tare) : 0;
    if (c > p_.full_scale) c = p_.full_scale;
    dev[static_cast<std::size_t>(k)] = c;
  }
  {
    std::lock_guard<std::mutex> lk(mu_);  // taxel_faults_ and rng_ are shared with the setters
    for (const TaxelFault& tf : taxel_faults_) {
      std::size_t k = map_.toDevice(tf.row * p_.cells.cols + tf.col);
      double v = dev[k];
      if (tf.kind == TaxelFaultKind::Dead) v = 0.0;
      else if (tf.kind == TaxelFaultKind::Stuck) v = tf.value;
      else v += tf.value * gaussian();
      v = std::round(v);
      dev[k] = static_cast<uint16_t>(v < 0.0 ? 0.0 : (v > p_.full_scale ? p_.full_scale : v));
    }
  }
  const bool rle = rle_.load();
  std::vector<uint8_t> payload(2 + 5 + 2 * static_cast<std::size_t>(n));
  std::size_t off = 0;
  if (with_status) {
    putU16(payload.data(), static_cast<uint16_t>(StatusCode::Success));
    off = 2;
  }
  putU32(payload.data() + off, t);
  payload[off + 4] = rle ? kFlagRle : 0;
  off += 5;
  off += encodeCells(dev.data(), n, rle, payload.data() + off, payload.size() - off);
  std::vector<uint8_t> pkt(off + kOverhead);
  pkt.resize(encodePacket(id, payload.data(), off, pkt.data(), pkt.size()));
  {
    std::lock_guard<std::mutex> lk(mu_);
    ++stats_.frames;
  }
  sendPacket(pkt);
}

void SimulatedWts::handle(const PacketView& pkt) {
  {
    std::lock_guard<std::mutex> lk(mu_);
    ++stats_.commands;
  }
  const uint16_t forced = forced_status_.load();
  if (forced != 0 && pkt.id != static_cast<uint8_t>(Command::Loop)) {
    reply(pkt.id, static_cast<StatusCode>(forced), nullptr, 0);
    return;
  }
  auto formatError = [&] {
    std::lock_guard<std::mutex> lk(mu_);
    ++stats_.bad_commands;
  };
  switch (static_cast<Command>(pkt.id)) {
    case Command::ReadSingleFrame:
      if (pkt.size != 1) {
        formatError();
        reply(pkt.id, StatusCode::CmdFormatError, nullptr, 0);
        return;
      }
      rle_ = (pkt.payload[0] & kFlagRle) != 0;
      sendFrame(pkt.id, true);
      return;
    case Command::StartPeriodic:
      if (pkt.size != 3) {
        formatError();
        reply(pkt.id, StatusCode::CmdFormatError, nullptr, 0);
        return;
      }
      if (streaming_) {
        reply(pkt.id, StatusCode::AlreadyRunning, nullptr, 0);
        return;
      }
      rle_ = (pkt.payload[0] & kFlagRle) != 0;
      delay_ms_ = getU16(pkt.payload + 1);
      streaming_ = true;  // before the reply: the host may check right after the ack
      reply(pkt.id, StatusCode::Success, nullptr, 0);
      return;
    case Command::StopPeriodic:
      streaming_ = false;
      reply(pkt.id, StatusCode::Success, nullptr, 0);
      return;
    case Command::Tare: {
      const bool on = pkt.size == 0 || pkt.payload[0] != 0;
      if (on) {
        RawTactileFrame f;
        {
          std::lock_guard<std::mutex> lk(mu_);
          if (source_) source_(nowMs(), f);
          else if (!recording_.empty()) f = recording_[rec_index_ % recording_.size()];
        }
        std::lock_guard<std::mutex> lk(mu_);
        for (int k = 0; k < map_.cells(); ++k) tare_[static_cast<std::size_t>(k)] = f.counts[map_.toSensing(k)];
      } else {
        std::lock_guard<std::mutex> lk(mu_);
        tare_.fill(0);
      }
      reply(pkt.id, StatusCode::Success, nullptr, 0);
      return;
    }
    case Command::MatrixInfo: {
      uint8_t d[10];
      putU16(d, static_cast<uint16_t>(map_.resX()));
      putU16(d + 2, static_cast<uint16_t>(map_.resY()));
      putU16(d + 4, p_.cell_size_10um);
      putU16(d + 6, p_.cell_size_10um);
      putU16(d + 8, p_.full_scale);
      reply(pkt.id, StatusCode::Success, d, sizeof(d));
      return;
    }
    case Command::SensorType: {
      const char t[] = "WTS0614-34 (simulated)";
      reply(pkt.id, StatusCode::Success, reinterpret_cast<const uint8_t*>(t), sizeof(t) - 1);
      return;
    }
    case Command::Temperature: {
      uint8_t d[2];
      putU16(d, static_cast<uint16_t>(253));  // 25.3 degC
      reply(pkt.id, StatusCode::Success, d, 2);
      return;
    }
    case Command::SystemInfo: {
      uint8_t d[8] = {0x01, 0x01, 0, 0, 0, 0, 0, 0};
      putU16(d + 2, 0x0100);
      putU32(d + 4, 12345);
      reply(pkt.id, StatusCode::Success, d, sizeof(d));
      return;
    }
    case Command::Loop:
      reply(pkt.id, StatusCode::Success, pkt.payload, pkt.size);
      return;
    case Command::FrameData:
      break;
  }
  formatError();
  reply(pkt.id, StatusCode::CmdUnknown, nullptr, 0);
}

void SimulatedWts::run() {
  Parser parser(Direction::Any);
  uint8_t buf[256];
  long long next_due = steadyMs();
  while (running_) {
    if (!plugged_) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      parser.reset();
      continue;
    }
    int m;
    {
      std::lock_guard<std::mutex> lk(mu_);
      m = master_;
    }
    if (m < 0) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      continue;
    }
    pollfd pfd{m, POLLIN, 0};
    const int pr = ::poll(&pfd, 1, 1);
    if (pr > 0 && (pfd.revents & POLLIN)) {
      ssize_t n;
      {
        std::lock_guard<std::mutex> lk(mu_);
        n = master_ >= 0 ? ::read(master_, buf, sizeof(buf)) : -1;
      }
      std::size_t off = 0;
      while (n > 0 && off < static_cast<std::size_t>(n)) {
        off += parser.feed(buf + off, static_cast<std::size_t>(n) - off);
        PacketView pkt;
        ParseStatus ps;
        while ((ps = parser.next(pkt)) != ParseStatus::NeedMore) {
          if (ps == ParseStatus::Packet) {
            handle(pkt);
          } else {
            std::lock_guard<std::mutex> lk(mu_);
            ++stats_.bad_commands;
          }
        }
      }
    }
    if (streaming_ && plugged_) {
      const long long now = steadyMs();
      if (now >= next_due) {
        sendFrame(static_cast<uint8_t>(Command::FrameData), false);
        const long long d = delay_ms_ < 1 ? 1 : delay_ms_;
        next_due = (now - next_due > 10 * d) ? now + d : next_due + d;
      }
    } else {
      next_due = steadyMs();
    }
  }
}

}  // namespace wts
}  // namespace tactile
