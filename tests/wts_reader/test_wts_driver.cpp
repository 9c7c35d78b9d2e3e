// The real driver (SerialPort + Parser + FrameDecoder) against the simulated
// WTS on a pseudo-terminal: streaming, single-frame polling, RLE, fault
// injection, stalls, unplug/replug, tare, device errors, configuration errors,
// allocation-free poll(), and the wts_read tool end to end (also piped into
// tactile_features).
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "alloc_counter.hpp"
#include "tactile_wts/driver.hpp"
#include "tactile_wts/params_io.hpp"
#include "tactile_features/calibration.hpp"
#include "tactile_sim_contact/elastic_pad.hpp"
#include "tactile_wts/sim_device.hpp"
#include "wts_test_util.hpp"

using namespace tactile::wts;

namespace {

double nowS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// A frame that is a known function of the device timestamp, so every received
// frame can be checked exactly: counts[i] = (37 i + t) mod 4096, {s} order.
void pattern(uint32_t t, tactile::RawTactileFrame& f) {
  for (int i = 0; i < 84; ++i) f.counts[static_cast<std::size_t>(i)] = static_cast<uint16_t>((37 * i + t) % 4096);
}
bool matchesPattern(const tactile::RawTactileFrame& f) {
  if (f.rows != 6 || f.cols != 14) return false;
  for (int i = 0; i < 84; ++i)
    if (f.counts[static_cast<std::size_t>(i)] != (37 * i + f.device_time_ms) % 4096) return false;
  return true;
}

struct TempDir {
  std::string path;
  TempDir() {
    char t[] = "/tmp/wts_test_XXXXXX";
    path = mkdtemp(t);
  }
  ~TempDir() { std::system(("rm -rf " + path).c_str()); }
};

class WtsPty : public ::testing::Test {
 protected:
  void SetUp() override {
    SimulatedWts::Params sp;
    sp.link = dir.path + "/wts0";
    sim.setSource(pattern);
    std::string why;
    ASSERT_TRUE(sim.start(sp, &why)) << why;
    params.device = sim.path();
    params.periodic_ms = 2;
    params.reconnect_period_s = 0.05;
  }
  void TearDown() override { sim.stop(); }

  /// Polls until `n` frames arrived or `max_s` passed; counts statuses.
  int collect(WtsDriver& d, int n, double max_s, int* bad = nullptr, std::vector<ReadStatus>* seen = nullptr) {
    tactile::RawTactileFrame f;
    int frames = 0;
    const double t_end = nowS() + max_s;
    while (frames < n && nowS() < t_end) {
      const double now = nowS();
      const ReadStatus st = d.poll(now, 20, f);
      if (seen && (seen->empty() || seen->back() != st)) seen->push_back(st);
      if (st == ReadStatus::NewFrame) {
        ++frames;
        if (!(f.time_s <= now)) ++stamped_after_poll;  // taken before it was read (device_clock.hpp)
        if (!matchesPattern(f) && bad) ++*bad;
      } else if (st == ReadStatus::Disconnected) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
    }
    return frames;
  }

  TempDir dir;
  SimulatedWts sim;
  WtsParams params;
  int stamped_after_poll = 0;
};

}  // namespace

TEST_F(WtsPty, StreamsPeriodicFramesExactlyPlainAndRle) {
  for (bool rle : {false, true}) {
    WtsDriver d;
    params.rle = rle;
    ASSERT_TRUE(d.configure(params).ok());
    std::string why;
    ASSERT_EQ(d.open(&why), CmdStatus::Ok) << why;
    EXPECT_TRUE(sim.streaming());
    EXPECT_EQ(sim.rleRequested(), rle);
    int bad = 0;
    EXPECT_EQ(collect(d, 100, 5.0, &bad), 100) << "rle " << rle;
    EXPECT_EQ(bad, 0);
    EXPECT_EQ(stamped_after_poll, 0);
    EXPECT_EQ(d.clockStats().restarts, 0u) << "the simulated device's stamps advance";
    EXPECT_EQ(d.parserStats().crc_errors, 0u);
    d.close();
    EXPECT_FALSE(sim.streaming()) << "close() stops periodic acquisition";
  }
}

// The elastic pad simulator (core/sim/contact) behind the simulated device: a
// sphere pressed off-centre; its taxel forces are turned into 12-bit counts at
// the inverse of the default calibration, sent over the PTY, decoded and
// calibrated back to newtons.
TEST_F(WtsPty, PadSimulatorFramesSurviveTheLinkToNewtons) {
  constexpr double kNPerCount = 0.002;  // CalibrationParams default c1
  tactile::sim::PadGeometry g;
  tactile::TactileFrame truth_frame;
  tactile::sim::PadTruth truth;
  const double x0 = 0.006, y0 = -0.002, R = 0.02, depth = 0.002;
  tactile::sim::integratePad(
      g,
      [&](double x, double y) {
        const double r2 = (x - x0) * (x - x0) + (y - y0) * (y - y0);
        return r2 >= R * R ? 0.0 : depth - (R - std::sqrt(R * R - r2));
      },
      truth_frame, &truth);
  ASSERT_GT(truth.force, 1.0);
  sim.setSource([&](uint32_t, tactile::RawTactileFrame& f) {
    for (int i = 0; i < 84; ++i) {
      const double c = std::round(truth_frame.force[static_cast<std::size_t>(i)] / kNPerCount);
      f.counts[static_cast<std::size_t>(i)] = static_cast<uint16_t>(c > 4095 ? 4095 : c);
    }
  });
  // The simulator's thread calls the source until TearDown() stops it, after
  // this body's locals (truth_frame) are gone: drop the source first, on
  // every way out (ASan: stack-use-after-return).
  struct DropSource {
    tactile::wts::SimulatedWts& s;
    ~DropSource() { s.setSource(nullptr); }
  } drop_source{sim};
  params.rle = true;
  WtsDriver d;
  ASSERT_TRUE(d.configure(params).ok());
  ASSERT_EQ(d.open(), CmdStatus::Ok);
  tactile::Calibration cal;
  ASSERT_TRUE(cal.configure(tactile::CalibrationParams{}).ok());
  tactile::RawTactileFrame raw;
  bool got = false;
  for (double t_end = nowS() + 2.0; nowS() < t_end && !got;) got = d.poll(nowS(), 20, raw) == ReadStatus::NewFrame;
  ASSERT_TRUE(got);
  tactile::TactileFrame f;
  ASSERT_EQ(cal.step(raw, f), tactile::CalibrationStatus::Ok);
  // tolerance: half a count of quantization per taxel (0.001 N), none saturates here
  double sum = 0;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 14; ++c) {
      EXPECT_NEAR(f.at(r, c), truth_frame.at(r, c), 0.5 * kNPerCount + 1e-12) << r << "," << c;
      sum += f.at(r, c);
    }
  EXPECT_NEAR(sum, truth.force, 84 * 0.5 * kNPerCount);
  EXPECT_EQ(f.saturated_count, 0);
}

TEST_F(WtsPty, ServesARecordingInOrder) {
  std::vector<tactile::RawTactileFrame> rec(3);
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 84; ++i) rec[static_cast<std::size_t>(k)].counts[static_cast<std::size_t>(i)] =
        static_cast<uint16_t>(1000 * k + i);
  sim.setRecording(rec);
  params.periodic_ms = 0;  // one frame per request: no frame can be superseded by a newer one
  WtsDriver d;
  ASSERT_TRUE(d.configure(params).ok());
  ASSERT_EQ(d.open(), CmdStatus::Ok);
  tactile::RawTactileFrame f;
  std::vector<int> order;
  for (double t_end = nowS() + 2.0; nowS() < t_end && order.size() < 7;)
    if (d.poll(nowS(), 20, f) == ReadStatus::NewFrame) {
      const int k = f.counts[0] / 1000;
      for (int i = 0; i < 84; ++i) ASSERT_EQ(f.counts[static_cast<std::size_t>(i)], 1000 * k + i);
      order.push_back(k);
    }
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 0, 1, 2, 0}));
}

TEST_F(WtsPty, SingleFramePolling) {
  params.periodic_ms = 0;
  params.rle = true;
  WtsDriver d;
  ASSERT_TRUE(d.configure(params).ok());
  std::string why;
  ASSERT_EQ(d.open(&why), CmdStatus::Ok) << why;
  EXPECT_FALSE(sim.streaming());
  int bad = 0;
  EXPECT_EQ(collect(d, 30, 5.0, &bad), 30);
  EXPECT_EQ(bad, 0);
}

TEST_F(WtsPty, FaultInjectionNeverYieldsAWrongFrameAndKeepsDelivering) {
  WtsDriver d;
  ASSERT_TRUE(d.configure(params).ok());
  std::string why;
  ASSERT_EQ(d.open(&why), CmdStatus::Ok) << why;
  SimFaults f;
  f.bit_flip = 0.05;
  f.drop_byte = 0.05;
  f.truncate = 0.05;
  f.bad_crc = 0.05;
  f.garbage = 0.05;
  f.seed = 7;
  sim.setFaults(f);
  int bad = 0;
  const int got = collect(d, 400, 20.0, &bad);
  EXPECT_EQ(got, 400);
  EXPECT_EQ(bad, 0) << "a corrupted frame was delivered";
  EXPECT_GT(sim.stats().faults, 20u);
  EXPECT_GT(d.parserStats().crc_errors + d.parserStats().skipped_bytes, 0u);
  std::printf("[faults] %llu faulted packets, %llu CRC errors, %llu skipped bytes, %llu bad frames; 400 frames ok\n",
              static_cast<unsigned long long>(sim.stats().faults),
              static_cast<unsigned long long>(d.parserStats().crc_errors),
              static_cast<unsigned long long>(d.parserStats().skipped_bytes),
              static_cast<unsigned long long>(d.stats().bad_frames));
}

TEST_F(WtsPty, StallGivesNoDataThenRecovers) {
  WtsDriver d;
  ASSERT_TRUE(d.configure(params).ok());
  ASSERT_EQ(d.open(), CmdStatus::Ok);
  ASSERT_GT(collect(d, 5, 2.0), 0);
  SimFaults f;
  f.stall = 1.0;
  f.stall_ms = 300;
  sim.setFaults(f);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  // drain what was already queued, then the device is silent
  tactile::RawTactileFrame fr;
  int nodata = 0;
  const double t_end = nowS() + 0.25;
  while (nowS() < t_end)
    if (d.poll(nowS(), 20, fr) == ReadStatus::NoData) ++nodata;
  EXPECT_GT(nodata, 3);
  sim.setFaults(SimFaults{});
  int bad = 0;
  EXPECT_EQ(collect(d, 20, 3.0, &bad), 20);
  EXPECT_EQ(bad, 0);
}

TEST_F(WtsPty, UnplugGivesDisconnectedThenReconnects) {
  WtsDriver d;
  ASSERT_TRUE(d.configure(params).ok());
  ASSERT_EQ(d.open(), CmdStatus::Ok);
  ASSERT_EQ(collect(d, 10, 2.0), 10);
  sim.unplug();
  tactile::RawTactileFrame f;
  bool disconnected = false;
  for (double t_end = nowS() + 2.0; nowS() < t_end && !disconnected;)
    disconnected = d.poll(nowS(), 20, f) == ReadStatus::Disconnected;
  ASSERT_TRUE(disconnected);
  EXPECT_FALSE(d.isOpen());
  // while unplugged: Disconnected, never a frame
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(d.poll(nowS(), 5, f), ReadStatus::Disconnected);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(sim.replug());
  std::vector<ReadStatus> seen;
  int bad = 0;
  EXPECT_EQ(collect(d, 10, 3.0, &bad, &seen), 10);
  EXPECT_EQ(bad, 0);
  EXPECT_NE(std::find(seen.begin(), seen.end(), ReadStatus::Reconnected), seen.end());
  EXPECT_EQ(d.stats().reconnects, 1u);
  EXPECT_GE(d.stats().disconnects, 1u);
}

TEST_F(WtsPty, SilentStreamStopIsRestartedByTheWatchdog) {
  params.restart_after_s = 0.2;
  WtsDriver d;
  ASSERT_TRUE(d.configure(params).ok());
  ASSERT_EQ(d.open(), CmdStatus::Ok);
  ASSERT_EQ(collect(d, 10, 2.0), 10);
  sim.resetDevice();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_FALSE(sim.streaming());
  int bad = 0;
  const double t0 = nowS();
  EXPECT_EQ(collect(d, 200, 3.0, &bad), 200);
  EXPECT_EQ(bad, 0);
  EXPECT_GE(d.stats().restarts, 1u);
  EXPECT_TRUE(sim.streaming());
  EXPECT_LT(nowS() - t0, 2.0);
}

TEST_F(WtsPty, DeviceTareZeroesTheFrames) {
  sim.setSource([](uint32_t, tactile::RawTactileFrame& f) {
    for (int i = 0; i < 84; ++i) f.counts[static_cast<std::size_t>(i)] = static_cast<uint16_t>(500 + i);
  });
  WtsDriver d;
  ASSERT_TRUE(d.configure(params).ok());
  ASSERT_EQ(d.open(), CmdStatus::Ok);
  auto lastFrame = [&](tactile::RawTactileFrame& out) {
    int n = 0;
    for (double t_end = nowS() + 2.0; nowS() < t_end && n < 10;)
      if (d.poll(nowS(), 20, out) == ReadStatus::NewFrame) ++n;
    return n;
  };
  tactile::RawTactileFrame f;
  ASSERT_GT(lastFrame(f), 0);
  EXPECT_EQ(f.counts[10], 510);
  ASSERT_EQ(d.tare(true), CmdStatus::Ok);
  ASSERT_GT(lastFrame(f), 0);
  for (int i = 0; i < 84; ++i) EXPECT_EQ(f.counts[static_cast<std::size_t>(i)], 0) << i;
  ASSERT_EQ(d.tare(false), CmdStatus::Ok);
  ASSERT_GT(lastFrame(f), 0);
  EXPECT_EQ(f.counts[10], 510);
}

TEST_F(WtsPty, DeviceErrorIsReportedWithItsName) {
  sim.forceStatus(StatusCode::NotInitialized);
  WtsDriver d;
  ASSERT_TRUE(d.configure(params).ok());
  std::string why;
  EXPECT_EQ(d.open(&why), CmdStatus::DeviceError);
  EXPECT_NE(why.find("E_NOT_INITIALIZED"), std::string::npos) << why;
  EXPECT_STREQ(toString(d.lastDeviceStatus()), "E_NOT_INITIALIZED");
}

TEST_F(WtsPty, SingleFrameDeviceErrorGivesDeviceErrorStatus) {
  params.periodic_ms = 0;
  params.check_matrix_info = false;
  WtsDriver d;
  ASSERT_TRUE(d.configure(params).ok());
  ASSERT_EQ(d.open(), CmdStatus::Ok);
  sim.forceStatus(StatusCode::NoSensor);
  tactile::RawTactileFrame f;
  bool err = false;
  for (double t_end = nowS() + 2.0; nowS() < t_end && !err;) {
    const ReadStatus st = d.poll(nowS(), 20, f);
    ASSERT_NE(st, ReadStatus::NewFrame);
    err = st == ReadStatus::DeviceError;
  }
  EXPECT_TRUE(err);
  EXPECT_EQ(d.lastDeviceStatus(), StatusCode::NoSensor);
}

TEST_F(WtsPty, MatrixMismatchIsRefusedWithAClearMessage) {
  params.cells.transpose = false;  // expects res 14 x 6, the device says 6 x 14
  WtsDriver d;
  ASSERT_TRUE(d.configure(params).ok());
  std::string why;
  EXPECT_EQ(d.open(&why), CmdStatus::BadReply);
  EXPECT_NE(why.find("6 x 14"), std::string::npos) << why;
  EXPECT_NE(why.find("transpose"), std::string::npos) << why;
}

TEST_F(WtsPty, LoopEchoAndTemperature) {
  WtsDriver d;
  params.periodic_ms = 0;
  ASSERT_TRUE(d.configure(params).ok());
  ASSERT_EQ(d.open(), CmdStatus::Ok);
  const uint8_t msg[] = {1, 2, 0xAA, 0xAA, 0xAA, 9};
  bool ok = false;
  ASSERT_EQ(d.loop(msg, sizeof(msg), ok), CmdStatus::Ok);
  EXPECT_TRUE(ok);
  double t = 0;
  ASSERT_EQ(d.temperature(t), CmdStatus::Ok);
  EXPECT_NEAR(t, 25.3, 1e-9);
}

TEST(WtsDriverConfig, ErrorsNameParameterAndRange) {
  WtsDriver d;
  WtsParams p;
  p.periodic_ms = -1;
  auto r = d.configure(p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("wts.periodic_ms"), std::string::npos);
  EXPECT_NE(r.message().find("[0, 1000]"), std::string::npos);
  p.periodic_ms = 10;
  p.reconnect_period_s = 0.0;
  EXPECT_NE(d.configure(p).message().find("wts.reconnect_period_s"), std::string::npos);
  p.reconnect_period_s = 0.5;
  p.restart_after_s = 0.0;
  EXPECT_NE(d.configure(p).message().find("wts.restart_after_s"), std::string::npos);
  p.restart_after_s = 1.0;
  p.command_timeout_ms = 0;
  EXPECT_NE(d.configure(p).message().find("wts.command_timeout_ms"), std::string::npos);
  p.command_timeout_ms = 100;
  p.device = "";
  EXPECT_NE(d.configure(p).message().find("wts.device"), std::string::npos);
  tactile::RawTactileFrame f;
  WtsDriver unconfigured;
  EXPECT_EQ(unconfigured.poll(0.0, 0, f), ReadStatus::NotConfigured);
}

TEST(WtsParamsYaml, LoadsEveryKeyAndRejectsBadOnes) {
  WtsParams p;
  const tactile::config::Where where{"params.yaml", "wts"};
  YAML::Node n = YAML::Load(
      "{device: /dev/ttyACM3, rows: 6, cols: 14, transpose: false, flip_rows: true, flip_cols: true,"
      " periodic_ms: 5, rle: true, command_timeout_ms: 100, reconnect_period_s: 0.2, restart_after_s: 2.0,"
      " check_matrix_info: false}");
  ASSERT_TRUE(loadWtsParams(n, where, p).ok());
  EXPECT_EQ(p.device, "/dev/ttyACM3");
  EXPECT_FALSE(p.cells.transpose);
  EXPECT_TRUE(p.cells.flip_rows);
  EXPECT_TRUE(p.cells.flip_cols);
  EXPECT_EQ(p.periodic_ms, 5);
  EXPECT_TRUE(p.rle);
  EXPECT_EQ(p.command_timeout_ms, 100);
  EXPECT_DOUBLE_EQ(p.reconnect_period_s, 0.2);
  EXPECT_DOUBLE_EQ(p.restart_after_s, 2.0);
  EXPECT_FALSE(p.check_matrix_info);
  auto r = loadWtsParams(YAML::Load("{periodic_ms: 5000}"), where, p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("params.yaml"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("wts.periodic_ms = 5000"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("[0, 1000]"), std::string::npos) << r.message();
  r = loadWtsParams(YAML::Load("{perodic_ms: 5}"), where, p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("perodic_ms"), std::string::npos) << r.message();
  r = loadWtsParams(YAML::Load("{rows: six}"), where, p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("wts.rows"), std::string::npos) << r.message();
}

TEST(WtsDriverConfig, MissingDeviceFailsCleanly) {
  WtsDriver d;
  WtsParams p;
  p.device = "/nonexistent/ttyACM9";
  ASSERT_TRUE(d.configure(p).ok());
  std::string why;
  EXPECT_EQ(d.open(&why), CmdStatus::NotOpen);
  EXPECT_NE(why.find("/nonexistent/ttyACM9"), std::string::npos) << why;
  tactile::RawTactileFrame f;
  EXPECT_EQ(d.poll(0.0, 0, f), ReadStatus::Disconnected);
}

TEST(WtsSerialPort, RawModeBoundedReadsAndHangup) {
  const int m = posix_openpt(O_RDWR | O_NOCTTY);
  ASSERT_GE(m, 0);
  ASSERT_EQ(grantpt(m), 0);
  ASSERT_EQ(unlockpt(m), 0);
  char name[128];
  ASSERT_EQ(ptsname_r(m, name, sizeof(name)), 0);
  SerialPort port;
  ASSERT_EQ(port.open(name), IoStatus::Ok);
  // termios as documented: raw 115200 8N1
  const int fd = ::open(name, O_RDWR | O_NOCTTY);
  ASSERT_GE(fd, 0);
  termios tio{};
  ASSERT_EQ(tcgetattr(fd, &tio), 0);
  EXPECT_EQ(cfgetispeed(&tio), static_cast<speed_t>(B115200));
  EXPECT_EQ(cfgetospeed(&tio), static_cast<speed_t>(B115200));
  EXPECT_EQ(tio.c_cflag & CSIZE, static_cast<tcflag_t>(CS8));
  EXPECT_EQ(tio.c_cflag & (PARENB | CSTOPB), 0u);
  EXPECT_EQ(tio.c_lflag & (ICANON | ECHO | ISIG), 0u);
  EXPECT_EQ(tio.c_iflag & (IXON | ICRNL), 0u);
  ::close(fd);
  // bounded read: nothing there -> Timeout after about the timeout (generous upper bound for a loaded machine)
  uint8_t buf[64];
  std::size_t got = 99;
  const double t0 = nowS();
  EXPECT_EQ(port.read(buf, sizeof(buf), 30, got), IoStatus::Timeout);
  const double dt = nowS() - t0;
  EXPECT_EQ(got, 0u);
  EXPECT_GE(dt, 0.025);
  EXPECT_LT(dt, 0.5);
  // bytes pass unchanged (raw: no CR/LF translation, 0xFF, 0x00, ^C)
  const uint8_t msg[] = {0x0D, 0x0A, 0xFF, 0x00, 0x03, 0x11, 0x13, 0xAA};
  ASSERT_EQ(::write(m, msg, sizeof(msg)), static_cast<ssize_t>(sizeof(msg)));
  ASSERT_EQ(port.read(buf, sizeof(buf), 200, got), IoStatus::Ok);
  ASSERT_EQ(got, sizeof(msg));
  EXPECT_EQ(std::memcmp(buf, msg, sizeof(msg)), 0);
  ASSERT_EQ(port.write(msg, sizeof(msg), 100), IoStatus::Ok);
  uint8_t back[16];
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(::read(m, back, sizeof(back)), static_cast<ssize_t>(sizeof(msg)));
  // hangup: the master goes away -> Disconnected, port closed
  ::close(m);
  EXPECT_EQ(port.read(buf, sizeof(buf), 100, got), IoStatus::Disconnected);
  EXPECT_FALSE(port.isOpen());
  EXPECT_EQ(port.read(buf, sizeof(buf), 0, got), IoStatus::NotOpen);
  EXPECT_EQ(port.write(msg, 1, 0), IoStatus::NotOpen);
  SerialPort missing;
  EXPECT_EQ(missing.open("/nonexistent/ttyUSB7"), IoStatus::OpenFailed);
  EXPECT_EQ(missing.lastErrno(), ENOENT);
}

// poll() over a real PTY, driven from this thread only (no simulator thread,
// whose allocations would count): frames, corrupted frames and garbage are
// written to the master; the driver's single-frame requests are drained.
TEST(WtsDriverAlloc, PollDoesNotAllocateOverARealPty) {
  std::string slave;
  const int m = wtstest::openBarePty(slave);
  ASSERT_GE(m, 0);
  const char* name = slave.c_str();
  WtsParams p;
  p.device = name;
  p.periodic_ms = 0;  // single-frame polling: poll() also writes a request each cycle
  p.check_matrix_info = false;
  WtsDriver d;
  ASSERT_TRUE(d.configure(p).ok());
  ASSERT_EQ(d.open(), CmdStatus::Ok);
  CellMap map;
  map.configure(CellMapParams{});
  std::vector<std::vector<uint8_t>> pkts;
  for (int k = 0; k < 20; ++k) {
    tactile::RawTactileFrame f;
    pattern(static_cast<uint32_t>(k * 10), f);
    auto pkt = wtstest::framePacket(map, f.counts.data(), static_cast<uint32_t>(k * 10), k % 2 == 0, 0x20);
    if (k % 4 == 3) pkt[30] ^= 0x01;  // CRC error
    if (k % 5 == 4) pkt.insert(pkt.begin(), {0xAA, 0x00, 0xAA, 0xAA});  // garbage
    pkts.push_back(pkt);
  }
  tactile::RawTactileFrame f;
  uint8_t sink[512];
  int frames = 0, wrong = 0, other = 0;
  double t = 0.0;
  std::size_t allocs = 0;
  {
    tactile::test::AllocationScope scope;
    for (int it = 0; it < 200; ++it) {
      const auto& pkt = pkts[static_cast<std::size_t>(it) % pkts.size()];
      if (::write(m, pkt.data(), pkt.size()) != static_cast<ssize_t>(pkt.size())) ++other;
      t += 0.001;
      // poll until this packet has been consumed (PTY delivery is asynchronous:
      // it may arrive in pieces); returns as soon as bytes arrive
      ReadStatus st = ReadStatus::NoData;
      for (int tries = 0; tries < 5 && st == ReadStatus::NoData; ++tries) st = d.poll(t, 200, f);
      if (st == ReadStatus::NewFrame) {
        ++frames;
        if (!matchesPattern(f)) ++wrong;
      }
      while (::read(m, sink, sizeof(sink)) > 0) {
      }
    }
    allocs = scope.count();
  }
  EXPECT_EQ(allocs, 0u);
  EXPECT_EQ(other, 0);
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(frames, 150);  // 15 of every 20 packets are intact
  d.close();
  ::close(m);
}

// ---- the wts_read tool, end to end -----------------------------------------

namespace {
std::string run(const std::string& cmd, int* status = nullptr) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof(buf), p)) > 0) out.append(buf, n);
  const int st = pclose(p);
  if (status) *status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return out;
}
std::vector<std::vector<double>> csv(const std::string& text) {
  std::vector<std::vector<double>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::istringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) v.push_back(std::stod(cell));
    rows.push_back(v);
  }
  return rows;
}
}  // namespace

class WtsReadTool : public WtsPty {
 protected:
  void SetUp() override {
    WtsPty::SetUp();
    // one pressed taxel at {s} (r=2, c=9): 1000 counts
    sim.setSource([](uint32_t, tactile::RawTactileFrame& f) {
      f.counts.fill(0);
      f.counts[2 * 14 + 9] = 1000;
    });
  }
};

TEST_F(WtsReadTool, RawAndNewtonCsvInSensingOrder) {
  for (const std::string opts : {"--periodic-ms 5", "--periodic-ms 5 --rle", "", "--rle"}) {
    int st = -1;
    const auto raw = csv(run(std::string(WTS_READ_BIN) + " --device " + sim.path() + " --count 4 --raw " + opts, &st));
    EXPECT_EQ(st, 0) << opts;
    ASSERT_EQ(raw.size(), 4u) << opts;
    for (const auto& r : raw) {
      ASSERT_EQ(r.size(), 84u);
      for (int i = 0; i < 84; ++i) EXPECT_EQ(r[static_cast<std::size_t>(i)], i == 37 ? 1000.0 : 0.0) << opts << " " << i;
    }
    const auto n = csv(run(std::string(WTS_READ_BIN) + " --device " + sim.path() + " --count 3 " + opts, &st));
    ASSERT_EQ(n.size(), 3u);
    // default calibration 0.002 N/count: 1000 counts = 2 N (printed %.6g: exact)
    for (const auto& r : n) EXPECT_DOUBLE_EQ(r[37], 2.0);
  }
}

TEST_F(WtsReadTool, ParamsFileGivesDeviceAndCalibration) {
  const std::string file = dir.path + "/params.yaml";
  FILE* f = std::fopen(file.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fprintf(f, "wts:\n  device: %s\n  periodic_ms: 5\n  rle: true\ncalibration:\n  coeffs: [0, 0.004]\n",
               sim.path().c_str());
  std::fclose(f);
  int st = -1;
  const auto rows = csv(run(std::string(WTS_READ_BIN) + " --params " + file + " --count 2", &st));
  EXPECT_EQ(st, 0);
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& r : rows) EXPECT_DOUBLE_EQ(r[37], 4.0);  // 1000 counts * 0.004 N/count
  EXPECT_TRUE(sim.rleRequested());
}

TEST_F(WtsReadTool, PipesIntoTactileFeatures) {
  const std::string out = run(std::string(WTS_READ_BIN) + " --device " + sim.path() +
                              " --periodic-ms 5 --count 5 | " + TACTILE_FEATURES_BIN + " -");
  int lines = 0;
  std::istringstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    ++lines;
    double cop_x = NAN, cop_y = NAN, force = NAN;
    const char* p = std::strstr(line.c_str(), "\"cop_x\":");
    ASSERT_NE(p, nullptr) << line;
    std::sscanf(p, "\"cop_x\":%lf", &cop_x);
    std::sscanf(std::strstr(line.c_str(), "\"cop_y\":"), "\"cop_y\":%lf", &cop_y);
    std::sscanf(std::strstr(line.c_str(), "\"force\":"), "\"force\":%lf", &force);
    // taxel (r=2, c=9): x = (9 - 6.5) * 3.4 mm, y = (2 - 2.5) * 3.4 mm; printed %.9g -> 1e-9
    EXPECT_NEAR(cop_x, 2.5 * 0.0034, 1e-9);
    EXPECT_NEAR(cop_y, -0.5 * 0.0034, 1e-9);
    EXPECT_NEAR(force, 2.0, 1e-9);
  }
  EXPECT_EQ(lines, 5);
}

TEST_F(WtsReadTool, LinkErrorsGoToStderrAndMissingDeviceExits1) {
  int st = -1;
  const std::string out = run(std::string(WTS_READ_BIN) + " --device /nonexistent/tty 2>&1", &st);
  EXPECT_EQ(st, 1);
  EXPECT_NE(out.find("cannot open /nonexistent/tty"), std::string::npos) << out;
  EXPECT_EQ(run(std::string(WTS_READ_BIN) + " --periodic-ms 0 --device x 2>&1", &st).find("[1, 1000]") ==
                std::string::npos,
            false);
  EXPECT_EQ(st, 2);
  // with corruption, stdout stays clean CSV and stderr reports the errors
  SimFaults f;
  f.bad_crc = 0.3;
  f.seed = 3;
  const std::string err_file = dir.path + "/err.txt";
  // faults switched on after the tool opened the device: give it time to open first
  std::thread later([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    sim.setFaults(f);
  });
  const auto rows = csv(run(std::string(WTS_READ_BIN) + " --device " + sim.path() + " --periodic-ms 5 --count 100 --raw 2>" + err_file, &st));
  later.join();
  EXPECT_EQ(st, 0);
  ASSERT_EQ(rows.size(), 100u);
  for (const auto& r : rows) EXPECT_EQ(r[37], 1000.0);
  const std::string err = run("cat " + err_file);
  EXPECT_NE(err.find("link errors"), std::string::npos) << err;
}
