#include "tactile_wts/driver.hpp"

#include <cmath>
#include <cstring>
#include <ctime>

namespace tactile {
namespace wts {

namespace {
long long monoMs() {  // deadline clock of the blocking command calls (transport, not a core)
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<long long>(ts.tv_sec) * 1000 + ts.tv_nsec / 1000000;
}
}  // namespace

const char* toString(ReadStatus s) {
  switch (s) {
    case ReadStatus::NewFrame: return "NewFrame";
    case ReadStatus::NoData: return "NoData";
    case ReadStatus::LinkErrors: return "LinkErrors";
    case ReadStatus::DeviceError: return "DeviceError";
    case ReadStatus::Reconnected: return "Reconnected";
    case ReadStatus::Disconnected: return "Disconnected";
    case ReadStatus::NotConfigured: return "NotConfigured";
  }
  return "?";
}

const char* toString(CmdStatus s) {
  switch (s) {
    case CmdStatus::Ok: return "Ok";
    case CmdStatus::DeviceError: return "DeviceError";
    case CmdStatus::Timeout: return "Timeout";
    case CmdStatus::Disconnected: return "Disconnected";
    case CmdStatus::NotOpen: return "NotOpen";
    case CmdStatus::BadReply: return "BadReply";
  }
  return "?";
}

ConfigResult WtsDriver::configure(const WtsParams& p) {
  configured_ = false;
  if (p.device.empty() || p.device.size() >= 255)
    return rangeError("wts.device", "'" + p.device + "'", "must be a path of 1..254 characters");
  if (p.periodic_ms < 0 || p.periodic_ms > 1000)
    return rangeError("wts.periodic_ms", p.periodic_ms, "must be in [0, 1000] (0 = single-frame polling)");
  if (p.command_timeout_ms < 1 || p.command_timeout_ms > 10000)
    return rangeError("wts.command_timeout_ms", p.command_timeout_ms, "must be in [1, 10000]");
  if (!(p.reconnect_period_s >= 0.01 && p.reconnect_period_s <= 60.0))
    return rangeError("wts.reconnect_period_s", p.reconnect_period_s, "must be in [0.01, 60] (s)");
  if (!(p.restart_after_s >= 0.05 && p.restart_after_s <= 60.0))
    return rangeError("wts.restart_after_s", p.restart_after_s, "must be in [0.05, 60] (s)");
  ConfigResult r = decoder_.configure(p.cells);
  if (!r) return r;
  parser_ = Parser(Direction::FromDevice, p.cells.rows * p.cells.cols);
  p_ = p;
  configured_ = true;
  return ConfigResult::success();
}

CmdStatus WtsDriver::open(std::string* why) {
  if (!configured_) {
    if (why) *why = "not configured";
    return CmdStatus::NotOpen;
  }
  want_open_ = true;
  last_io_ = port_.open(p_.device.c_str());
  if (last_io_ != IoStatus::Ok) {
    if (why) *why = "cannot open " + p_.device + ": " + std::strerror(port_.lastErrno());
    return CmdStatus::NotOpen;
  }
  parser_.reset();
  clock_.reset();
  if (p_.check_matrix_info) {
    MatrixInfo mi;
    const CmdStatus s = matrixInfo(mi);
    if (s != CmdStatus::Ok) {
      if (why) *why = std::string("matrix info (0x30) failed: ") + toString(s) +
                      (s == CmdStatus::DeviceError ? std::string(" ") + toString(last_status_) : std::string());
      return s;
    }
    const CellMap& m = decoder_.map();
    if (mi.res_x != m.resX() || mi.res_y != m.resY()) {
      if (why)
        *why = "device reports a " + std::to_string(mi.res_x) + " x " + std::to_string(mi.res_y) +
               " matrix (res_x x res_y), the configured cell map expects " + std::to_string(m.resX()) + " x " +
               std::to_string(m.resY()) + " (wts.rows/cols/transpose)";
      return CmdStatus::BadReply;
    }
  }
  const CmdStatus s = startAcquisition();
  if (s != CmdStatus::Ok && why)
    *why = std::string("start periodic (0x21) failed: ") + toString(s) + " " + toString(last_status_);
  return s;
}

void WtsDriver::close() {
  if (port_.isOpen() && p_.periodic_ms > 0) stopPeriodic();
  port_.close();
  want_open_ = false;
}

CmdStatus WtsDriver::startAcquisition() {
  request_outstanding_ = false;
  frame_clock_started_ = false;
  if (p_.periodic_ms == 0) return CmdStatus::Ok;
  const CmdStatus s = startPeriodic();
  if (s == CmdStatus::DeviceError && last_status_ == StatusCode::AlreadyRunning) return CmdStatus::Ok;
  return s;
}

CmdStatus WtsDriver::sendPacket(std::size_t len, int timeout_ms) {
  if (len == 0) return CmdStatus::BadReply;
  last_io_ = port_.write(tx_.data(), len, timeout_ms);
  if (last_io_ == IoStatus::Ok) return CmdStatus::Ok;
  if (last_io_ == IoStatus::Disconnected) {
    ++stats_.disconnects;
    return CmdStatus::Disconnected;
  }
  if (last_io_ == IoStatus::NotOpen) return CmdStatus::NotOpen;
  return CmdStatus::Timeout;
}

void WtsDriver::handlePacket(const PacketView& pkt, bool& got_frame, bool& link_error) {
  const bool is_frame = pkt.id == static_cast<uint8_t>(Command::FrameData) ||
                        (pkt.id == static_cast<uint8_t>(Command::ReadSingleFrame) && await_id_ != pkt.id);
  if (is_frame) {
    if (pkt.id == static_cast<uint8_t>(Command::ReadSingleFrame)) request_outstanding_ = false;
    const FrameStatus fs = decoder_.decode(pkt, latest_);
    if (fs == FrameStatus::Ok) {
      have_latest_ = true;
      got_frame = true;
      ++stats_.frames;
    } else if (fs == FrameStatus::DeviceError) {
      device_error_ = true;
      last_status_ = decoder_.deviceStatus();
    } else {
      ++stats_.bad_frames;
      link_error = true;
    }
    return;
  }
  if (pkt.id == await_id_ && !await_done_) {
    await_done_ = true;
    reply_size_ = pkt.size < reply_.size() ? pkt.size : static_cast<uint16_t>(reply_.size());
    if (reply_size_ > 0) std::memcpy(reply_.data(), pkt.payload, reply_size_);
    StatusCode st = StatusCode::CmdFormatError;
    pkt.status(st);
    last_status_ = st;
    return;
  }
  ++stats_.other_packets;
}

IoStatus WtsDriver::pump(int timeout_ms, bool& got_frame, bool& link_error) {
  std::size_t got = 0;
  last_io_ = port_.read(rx_.data(), rx_.size(), timeout_ms, got);
  if (last_io_ == IoStatus::Disconnected) {
    ++stats_.disconnects;
    return last_io_;
  }
  if (last_io_ != IoStatus::Ok) return last_io_;
  stats_.bytes += got;
  std::size_t off = 0;
  PacketView pkt;
  while (true) {
    off += parser_.feed(rx_.data() + off, got - off);
    ParseStatus ps;
    while ((ps = parser_.next(pkt)) != ParseStatus::NeedMore) {
      if (ps == ParseStatus::Packet)
        handlePacket(pkt, got_frame, link_error);
      else
        link_error = true;
    }
    if (off >= got) break;
  }
  return IoStatus::Ok;
}

CmdStatus WtsDriver::transact(Command c, const uint8_t* payload, uint16_t n) {
  if (!port_.isOpen()) return CmdStatus::NotOpen;
  const std::size_t len = encodePacket(static_cast<uint8_t>(c), payload, n, tx_.data(), tx_.size());
  await_id_ = static_cast<uint8_t>(c);
  await_done_ = false;
  CmdStatus s = sendPacket(len, p_.command_timeout_ms);
  if (s != CmdStatus::Ok) {
    await_id_ = 0xFF;
    return s;
  }
  const long long deadline = monoMs() + p_.command_timeout_ms;
  bool got_frame = false, link_error = false;
  while (!await_done_) {
    const long long left = deadline - monoMs();
    if (left <= 0) break;
    const IoStatus io = pump(static_cast<int>(left), got_frame, link_error);
    if (io == IoStatus::Disconnected) {
      await_id_ = 0xFF;
      return CmdStatus::Disconnected;
    }
  }
  await_id_ = 0xFF;
  if (!await_done_) return CmdStatus::Timeout;
  return last_status_ == StatusCode::Success ? CmdStatus::Ok : CmdStatus::DeviceError;
}

bool WtsDriver::kickPeriodic() {
  const std::size_t len =
      encodeStartPeriodic(p_.rle, static_cast<uint16_t>(p_.periodic_ms), tx_.data(), tx_.size());
  return sendPacket(len, 0) != CmdStatus::Disconnected;  // per-cycle path: never waits
}

CmdStatus WtsDriver::tare(bool on) {
  const uint8_t b = on ? 1 : 0;
  return transact(Command::Tare, &b, 1);
}

CmdStatus WtsDriver::startPeriodic() {
  uint8_t pl[3] = {static_cast<uint8_t>(p_.rle ? kFlagRle : 0), 0, 0};
  putU16(pl + 1, static_cast<uint16_t>(p_.periodic_ms));
  return transact(Command::StartPeriodic, pl, 3);
}

CmdStatus WtsDriver::stopPeriodic() { return transact(Command::StopPeriodic, nullptr, 0); }

CmdStatus WtsDriver::matrixInfo(MatrixInfo& info) {
  const CmdStatus s = transact(Command::MatrixInfo, nullptr, 0);
  if (s != CmdStatus::Ok) return s;
  PacketView v;
  v.id = static_cast<uint8_t>(Command::MatrixInfo);
  v.payload = reply_.data();
  v.size = reply_size_;
  return decodeMatrixInfo(v, info) ? CmdStatus::Ok : CmdStatus::BadReply;
}

CmdStatus WtsDriver::temperature(double& deg_c) {
  const CmdStatus s = transact(Command::Temperature, nullptr, 0);
  if (s != CmdStatus::Ok) return s;
  if (reply_size_ < 4) return CmdStatus::BadReply;
  deg_c = static_cast<int16_t>(getU16(reply_.data() + 2)) * 0.1;
  return CmdStatus::Ok;
}

CmdStatus WtsDriver::loop(const uint8_t* data, uint16_t n, bool& echoed_ok) {
  echoed_ok = false;
  if (n > reply_.size() - 2) return CmdStatus::BadReply;
  const CmdStatus s = transact(Command::Loop, data, n);
  if (s != CmdStatus::Ok) return s;
  echoed_ok = reply_size_ == n + 2 && (n == 0 || std::memcmp(reply_.data() + 2, data, n) == 0);
  return CmdStatus::Ok;
}

ReadStatus WtsDriver::poll(double now_s, int timeout_ms, RawTactileFrame& out) {
  if (!configured_) return ReadStatus::NotConfigured;
  if (!port_.isOpen()) {
    if (!want_open_) return ReadStatus::Disconnected;
    if (now_s - last_attempt_s_ < p_.reconnect_period_s) return ReadStatus::Disconnected;
    last_attempt_s_ = now_s;
    if (port_.reopen() != IoStatus::Ok) return ReadStatus::Disconnected;
    parser_.reset();
    clock_.reset();
    request_outstanding_ = false;
    frame_clock_started_ = false;
    if (p_.periodic_ms > 0 && !kickPeriodic()) {
      port_.close();
      return ReadStatus::Disconnected;
    }
    ++stats_.reconnects;
    return ReadStatus::Reconnected;
  }
  // periodic mode watchdog: no frame for restart_after_s -> send "start" again
  if (!frame_clock_started_) {
    frame_clock_started_ = true;
    last_frame_s_ = now_s;
  }
  if (p_.periodic_ms > 0 && now_s - last_frame_s_ > p_.restart_after_s) {
    last_frame_s_ = now_s;
    ++stats_.restarts;
    if (!kickPeriodic()) {
      last_attempt_s_ = now_s;
      return ReadStatus::Disconnected;
    }
  }
  // single-frame mode: keep one request outstanding (re-send after a timeout)
  if (p_.periodic_ms == 0 &&
      (!request_outstanding_ || now_s - request_time_s_ > 1e-3 * p_.command_timeout_ms)) {
    const std::size_t len = encodeReadSingleFrame(p_.rle, tx_.data(), tx_.size());
    const CmdStatus s = sendPacket(len, 0);  // never waits; not sent -> sent again next poll
    if (s == CmdStatus::Disconnected) {
      last_attempt_s_ = now_s;
      return ReadStatus::Disconnected;
    }
    request_outstanding_ = s == CmdStatus::Ok;
    request_time_s_ = now_s;
  }
  bool got_frame = false, link_error = false;
  device_error_ = false;
  if (!have_latest_) {
    IoStatus io = pump(timeout_ms, got_frame, link_error);
    // drain what is already there without waiting (bounded: 16 reads of 512 B)
    for (int k = 0; io == IoStatus::Ok && k < 16; ++k) io = pump(0, got_frame, link_error);
    if (io == IoStatus::Disconnected) {
      last_attempt_s_ = now_s;
      return ReadStatus::Disconnected;
    }
  } else {
    got_frame = true;  // a frame arrived during a command call
  }
  if (got_frame && have_latest_) {
    have_latest_ = false;
    last_frame_s_ = now_s;
    latest_.time_s = clock_.capture(latest_.device_time_ms, now_s);  // when taken, not when read
    latest_.seq = seq_++;
    out = latest_;
    return ReadStatus::NewFrame;
  }
  if (device_error_) return ReadStatus::DeviceError;
  return link_error ? ReadStatus::LinkErrors : ReadStatus::NoData;
}

}  // namespace wts
}  // namespace tactile
