// Protocol core of the WTS driver: CRC, packets, parser resynchronisation,
// frame decoding (plain and RLE), status names, the device -> {s} cell map,
// calibration to newtons, allocation-free per-frame path, fuzz smoke.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "tactile_features/calibration.hpp"
#include "tactile_wts/protocol.hpp"
#include "wts_test_util.hpp"

using namespace tactile::wts;
using wtstest::blobFrame;
using wtstest::framePacket;

namespace {

struct Collected {
  std::vector<std::vector<uint8_t>> payloads;
  std::vector<uint8_t> ids;
  std::vector<ParseStatus> errors;
};

// Feeds `bytes` in chunks of `chunk` and collects every event.
Collected parseAll(Parser& p, const std::vector<uint8_t>& bytes, std::size_t chunk) {
  Collected c;
  std::size_t off = 0;
  while (off < bytes.size()) {
    const std::size_t n = std::min(chunk, bytes.size() - off);
    std::size_t taken = 0;
    while (taken < n) {
      taken += p.feed(bytes.data() + off + taken, n - taken);
      PacketView v;
      ParseStatus st;
      while ((st = p.next(v)) != ParseStatus::NeedMore) {
        if (st == ParseStatus::Packet) {
          c.ids.push_back(v.id);
          c.payloads.emplace_back(v.payload, v.payload + v.size);
        } else {
          c.errors.push_back(st);
        }
      }
    }
    off += n;
  }
  return c;
}

CellMap defaultMap() {
  CellMap m;
  EXPECT_TRUE(m.configure(CellMapParams{}).ok());
  return m;
}

}  // namespace

TEST(WtsCrc, KnownVectorOfTheWireFormat) {
  // protocol.hpp's WIRE FORMAT: "AA AA AA 20 01 00 00 -> CRC bytes 8F 83"
  uint8_t buf[16];
  const std::size_t n = encodeReadSingleFrame(false, buf, sizeof(buf));
  const std::vector<uint8_t> got(buf, buf + n);
  const std::vector<uint8_t> want = {0xAA, 0xAA, 0xAA, 0x20, 0x01, 0x00, 0x00, 0x8F, 0x83};
  EXPECT_EQ(got, want);
  EXPECT_EQ(crc16(buf, 7), 0x838F);
}

TEST(WtsCrc, DetectsEverySingleBitFlipOfAFrame) {
  const CellMap m = defaultMap();
  uint16_t s[84];
  blobFrame(6, 14, 2, 7, s);
  const auto pkt = framePacket(m, s, 1234, false);
  int detected = 0, total = 0;
  for (std::size_t i = 0; i < pkt.size(); ++i)
    for (int b = 0; b < 8; ++b) {
      auto bad = pkt;
      bad[i] = static_cast<uint8_t>(bad[i] ^ (1 << b));
      Parser p;
      const Collected c = parseAll(p, bad, bad.size());
      ++total;
      // a flip may hit the preamble/size (never a packet) or the body (CRC error)
      detected += c.payloads.empty() ? 1 : 0;
    }
  EXPECT_EQ(detected, total);
}

TEST(WtsPacket, SingleFrameReplyIs183Bytes) {
  const CellMap m = defaultMap();
  uint16_t s[84] = {};
  const auto pkt = framePacket(m, s, 0, false, 0x20);
  EXPECT_EQ(pkt.size(), 183u);  // 3 preamble + id + 2 size + 2 status + 4 time + flags + 84 x 2 cells + 2 crc
  const auto periodic = framePacket(m, s, 0, false, 0x00);
  EXPECT_EQ(periodic.size(), 181u);  // no status code in periodic frames
}

TEST(WtsPacket, CommandEncodings) {
  uint8_t b[16];
  ASSERT_EQ(encodeStartPeriodic(true, 10, b, sizeof(b)), 11u);
  EXPECT_EQ(b[3], 0x21);
  EXPECT_EQ(getU16(b + 4), 3);
  EXPECT_EQ(b[6], kFlagRle);
  EXPECT_EQ(getU16(b + 7), 10);
  EXPECT_EQ(getU16(b + 9), crc16(b, 9));
  ASSERT_EQ(encodeStopPeriodic(b, sizeof(b)), 8u);
  EXPECT_EQ(b[3], 0x22);
  ASSERT_EQ(encodeTare(true, b, sizeof(b)), 9u);
  EXPECT_EQ(b[3], 0x23);
  EXPECT_EQ(b[6], 1);
  EXPECT_EQ(encodeSimple(Command::MatrixInfo, b, 7), 0u) << "must refuse a too small buffer";
  EXPECT_EQ(encodePacket(0x00, b, kMaxPayload + 1, b, sizeof(b)), 0u);
}

TEST(WtsStatus, NamesAndUnknown) {
  EXPECT_STREQ(toString(StatusCode::Success), "E_SUCCESS");
  EXPECT_STREQ(toString(StatusCode::ChecksumError), "E_CHECKSUM_ERROR");
  EXPECT_STREQ(toString(StatusCode::CmdUnknown), "E_CMD_UNKNOWN");
  EXPECT_STREQ(toString(StatusCode::FileExists), "E_FILE_EXISTS");
  EXPECT_STREQ(toString(static_cast<StatusCode>(31)), "E_UNKNOWN");
  EXPECT_STREQ(toString(static_cast<StatusCode>(0xFFFF)), "E_UNKNOWN");
  EXPECT_STREQ(commandName(0x21), "start periodic");
}

TEST(WtsParser, SamePacketsForEveryChunking) {
  const CellMap m = defaultMap();
  std::vector<uint8_t> stream;
  std::vector<std::vector<uint8_t>> sent;
  for (int k = 0; k < 8; ++k) {
    uint16_t s[84];
    blobFrame(6, 14, k % 6, (3 * k) % 14, s);
    const auto pkt = framePacket(m, s, static_cast<uint32_t>(100 * k), k % 2 == 1, k % 3 == 0 ? 0x20 : 0x00);
    sent.emplace_back(pkt.begin() + kHeaderLen, pkt.end() - kCrcLen);
    stream.insert(stream.end(), pkt.begin(), pkt.end());
  }
  for (std::size_t chunk : {1u, 2u, 3u, 7u, 64u, 181u, 183u, 500u, 5000u}) {
    Parser p;
    const Collected c = parseAll(p, stream, chunk);
    EXPECT_TRUE(c.errors.empty()) << "chunk " << chunk;
    EXPECT_EQ(c.payloads, sent) << "chunk " << chunk;
    EXPECT_EQ(p.stats().skipped_bytes, 0u);
  }
}

TEST(WtsParser, ResynchronisesAfterGarbageIncludingFalsePreambles) {
  const CellMap m = defaultMap();
  uint16_t s[84];
  blobFrame(6, 14, 3, 3, s);
  const auto pkt = framePacket(m, s, 7, false);
  std::vector<uint8_t> stream = {0x00, 0xAA, 0x13, 0xAA, 0xAA, 0x55, 0xAA, 0xAA, 0xAA, 0x20, 0x05};
  const std::size_t garbage = stream.size();
  stream.insert(stream.end(), pkt.begin(), pkt.end());
  stream.insert(stream.end(), {0xFF, 0xAA});  // trailing noise
  Parser p;
  const Collected c = parseAll(p, stream, 1);
  ASSERT_EQ(c.payloads.size(), 1u);
  EXPECT_EQ(c.payloads[0], std::vector<uint8_t>(pkt.begin() + kHeaderLen, pkt.end() - kCrcLen));
  EXPECT_GE(p.stats().skipped_bytes, garbage - 3);
  EXPECT_LE(p.buffered(), 2u);
}

TEST(WtsParser, TruncatedFrameThenGoodFrame) {
  const CellMap m = defaultMap();
  uint16_t a[84], b[84];
  blobFrame(6, 14, 1, 1, a);
  blobFrame(6, 14, 4, 12, b);
  const auto p1 = framePacket(m, a, 1, false);
  const auto p2 = framePacket(m, b, 2, false);
  std::vector<uint8_t> stream(p1.begin(), p1.begin() + 100);  // cut mid-payload
  stream.insert(stream.end(), p2.begin(), p2.end());
  Parser p;
  const Collected c = parseAll(p, stream, 16);
  ASSERT_EQ(c.payloads.size(), 1u) << "the good frame behind the truncated one must be found";
  EXPECT_EQ(c.payloads[0], std::vector<uint8_t>(p2.begin() + kHeaderLen, p2.end() - kCrcLen));
  EXPECT_FALSE(c.errors.empty());
  EXPECT_EQ(c.errors[0], ParseStatus::CrcError);
}

TEST(WtsParser, WrongCrcAndOversizeAreReportedThenRecovered) {
  const CellMap m = defaultMap();
  uint16_t s[84];
  blobFrame(6, 14, 2, 2, s);
  auto bad = framePacket(m, s, 1, false);
  bad.back() ^= 0xFF;
  const auto good = framePacket(m, s, 2, false);
  std::vector<uint8_t> stream = bad;
  const uint8_t huge[] = {0xAA, 0xAA, 0xAA, 0x00, 0xFF, 0xFF};  // size 65535 > kMaxPayload
  stream.insert(stream.end(), huge, huge + sizeof(huge));
  stream.insert(stream.end(), good.begin(), good.end());
  Parser p;
  const Collected c = parseAll(p, stream, stream.size());
  ASSERT_EQ(c.payloads.size(), 1u);
  EXPECT_EQ(getU32(c.payloads[0].data()), 2u);
  EXPECT_NE(std::find(c.errors.begin(), c.errors.end(), ParseStatus::CrcError), c.errors.end());
  EXPECT_NE(std::find(c.errors.begin(), c.errors.end(), ParseStatus::Oversize), c.errors.end());
  EXPECT_GE(p.stats().crc_errors, 1u);
  EXPECT_GE(p.stats().oversize, 1u);
}

TEST(WtsParser, DeviceDirectionRejectsImpossibleHeadersAtOnce) {
  const CellMap m = defaultMap();
  uint16_t s[84];
  blobFrame(6, 14, 2, 2, s);
  const auto good = framePacket(m, s, 5, false);
  uint8_t unknown[16];
  const uint8_t pl[2] = {0, 0};
  const std::size_t n = encodePacket(0x77, pl, 2, unknown, sizeof(unknown));  // CRC-valid, unknown id
  // false preamble whose size (0x0400) is legal overall but not for a 0x21 reply
  std::vector<uint8_t> stream = {0xAA, 0xAA, 0xAA, 0x21, 0x00, 0x04};
  stream.insert(stream.end(), unknown, unknown + n);
  stream.insert(stream.end(), good.begin(), good.end());
  Parser dev(Direction::FromDevice);
  const Collected c = parseAll(dev, stream, stream.size());
  ASSERT_EQ(c.payloads.size(), 1u) << "only the frame is accepted";
  EXPECT_EQ(c.ids[0], 0x00);
  EXPECT_EQ(dev.stats().bad_headers, 2u);
  EXPECT_EQ(dev.stats().crc_errors, 0u) << "no CRC attempted on impossible headers";
  // Any: the false 0x21 header (size 1024) holds everything behind it until
  // 1032 bytes have arrived -- the latency the direction filter avoids
  Parser any;
  const Collected c2 = parseAll(any, stream, stream.size());
  EXPECT_TRUE(c2.ids.empty());
  EXPECT_EQ(any.buffered(), stream.size());
  EXPECT_TRUE(plausibleHeader(Direction::FromDevice, 0x20, 175));
  EXPECT_TRUE(plausibleHeader(Direction::FromDevice, 0x20, 2));
  EXPECT_FALSE(plausibleHeader(Direction::FromDevice, 0x20, 3));
  EXPECT_FALSE(plausibleHeader(Direction::FromDevice, 0x00, 4));
  EXPECT_FALSE(plausibleHeader(Direction::FromDevice, 0x00, 5 + 2 * tactile::kMaxTaxels + 1));
  EXPECT_FALSE(plausibleHeader(Direction::FromDevice, 0xAA, 10));
  // with the configured 6x14 size, a 0x00 header longer than 5 + 168 is refused
  EXPECT_TRUE(plausibleHeader(Direction::FromDevice, 0x00, 173, 84));
  EXPECT_FALSE(plausibleHeader(Direction::FromDevice, 0x00, 174, 84));
  EXPECT_TRUE(plausibleHeader(Direction::FromDevice, 0x00, 174));
}

// ---- cell map: the one place where device order meets {s} ----------------------

TEST(WtsCellMap, DefaultWts0614MappingHandWorked) {
  // Device reports res_x = 6, res_y = 14 and sends x fastest: k = y*6 + x.
  // Default (transpose): {s} row r = x, col c = y, index r*14 + c.
  const CellMap m = defaultMap();
  EXPECT_EQ(m.resX(), 6);
  EXPECT_EQ(m.resY(), 14);
  EXPECT_EQ(m.toSensing(0), 0);        // (x0,y0) -> (r0,c0)
  EXPECT_EQ(m.toSensing(1), 14);       // (x1,y0) -> (r1,c0)
  EXPECT_EQ(m.toSensing(5), 70);       // (x5,y0) -> (r5,c0)
  EXPECT_EQ(m.toSensing(6), 1);        // (x0,y1) -> (r0,c1)
  EXPECT_EQ(m.toSensing(2 + 6 * 5), 2 * 14 + 5);
  EXPECT_EQ(m.toSensing(83), 83);      // (x5,y13) -> (r5,c13)
}

TEST(WtsCellMap, FlipsAndNoTransposeHandWorked) {
  CellMap m;
  CellMapParams p;
  p.transpose = false;  // device x along the 14-taxel side: k = y*14 + x, r = y, c = x
  ASSERT_TRUE(m.configure(p).ok());
  EXPECT_EQ(m.resX(), 14);
  EXPECT_EQ(m.resY(), 6);
  EXPECT_EQ(m.toSensing(15), 15);
  p.flip_rows = true;
  ASSERT_TRUE(m.configure(p).ok());
  EXPECT_EQ(m.toSensing(0), 5 * 14);  // (x0,y0) -> (r5,c0)
  p.flip_rows = false;
  p.flip_cols = true;
  ASSERT_TRUE(m.configure(p).ok());
  EXPECT_EQ(m.toSensing(0), 13);      // (x0,y0) -> (r0,c13)
}

TEST(WtsCellMap, IsABijectionForEveryOption) {
  for (int mask = 0; mask < 8; ++mask) {
    CellMapParams p;
    p.transpose = mask & 1;
    p.flip_rows = mask & 2;
    p.flip_cols = mask & 4;
    CellMap m;
    ASSERT_TRUE(m.configure(p).ok());
    std::vector<int> seen(84, 0);
    for (int k = 0; k < 84; ++k) {
      ASSERT_LT(m.toSensing(k), 84);
      ++seen[m.toSensing(k)];
      EXPECT_EQ(m.toDevice(m.toSensing(k)), k);
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), 84) << "mask " << mask;
  }
}

TEST(WtsCellMap, ConfigErrorsNameTheParameterAndRange) {
  CellMap m;
  CellMapParams p;
  p.rows = 0;
  const auto r = m.configure(p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("wts.rows"), std::string::npos);
  EXPECT_NE(r.message().find("[1, 16]"), std::string::npos);
  p.rows = 6;
  p.cols = 33;
  EXPECT_NE(m.configure(p).message().find("wts.cols"), std::string::npos);
}

// ---- frame decoding --------------------------------------------------------------

TEST(WtsDecoder, PlainAndRleGiveTheSameFrameInSensingOrder) {
  FrameDecoder d;
  ASSERT_TRUE(d.configure(CellMapParams{}).ok());
  uint16_t s[84];
  blobFrame(6, 14, 2, 9, s);
  s[0] = 4095;
  for (bool rle : {false, true}) {
    for (uint8_t id : {uint8_t(0x00), uint8_t(0x20)}) {
      const auto pkt = framePacket(d.map(), s, 4242, rle, id);
      Parser p;
      p.feed(pkt.data(), pkt.size());
      PacketView v;
      ASSERT_EQ(p.next(v), ParseStatus::Packet);
      tactile::RawTactileFrame f;
      ASSERT_EQ(d.decode(v, f), FrameStatus::Ok) << "rle " << rle << " id " << int(id);
      EXPECT_EQ(f.rows, 6);
      EXPECT_EQ(f.cols, 14);
      EXPECT_EQ(f.device_time_ms, 4242u);
      for (int i = 0; i < 84; ++i) ASSERT_EQ(f.counts[static_cast<std::size_t>(i)], s[i]) << "cell " << i;
    }
  }
  // the RLE packet of a sparse contact is much shorter
  EXPECT_LT(framePacket(d.map(), s, 0, true).size(), framePacket(d.map(), s, 0, false).size() / 2);
}

TEST(WtsDecoder, RejectsMalformedFramesWithAStatus) {
  FrameDecoder d;
  ASSERT_TRUE(d.configure(CellMapParams{}).ok());
  tactile::RawTactileFrame f;
  f.counts[0] = 77;
  uint8_t pl[2 + 5 + 168] = {};
  PacketView v{0x00, pl, 5 + 166};
  EXPECT_EQ(d.decode(v, f), FrameStatus::BadSize);
  v.size = 5 + 168;
  putU16(pl + 5 + 10, 0x1000);  // bits above 12 in a plain frame
  EXPECT_EQ(d.decode(v, f), FrameStatus::OutOfRange);
  // RLE: runs covering 83 or 85 cells
  std::memset(pl, 0, sizeof(pl));
  pl[4] = kFlagRle;
  int w = 5;
  for (int k = 0; k < 5; ++k, w += 2) putU16(pl + w, static_cast<uint16_t>((15 << 12) | 1));  // 75 cells
  putU16(pl + w, static_cast<uint16_t>((8 << 12) | 1));  // 83
  v.size = static_cast<uint16_t>(w + 2);
  EXPECT_EQ(d.decode(v, f), FrameStatus::BadRle);
  putU16(pl + w, static_cast<uint16_t>((10 << 12) | 1));  // 85
  EXPECT_EQ(d.decode(v, f), FrameStatus::BadRle);
  putU16(pl + w, static_cast<uint16_t>((9 << 12) | 1));  // 84: ok
  EXPECT_EQ(d.decode(v, f), FrameStatus::Ok);
  // a single-frame reply with an error status
  uint8_t err[2];
  putU16(err, static_cast<uint16_t>(StatusCode::NoSensor));
  PacketView e{0x20, err, 2};
  EXPECT_EQ(d.decode(e, f), FrameStatus::DeviceError);
  EXPECT_STREQ(toString(d.deviceStatus()), "E_NO_SENSOR");
  PacketView other{0x30, pl, 12};
  EXPECT_EQ(d.decode(other, f), FrameStatus::NotAFrame);
  FrameDecoder unconfigured;
  EXPECT_EQ(unconfigured.decode(v, f), FrameStatus::NotConfigured);
}

TEST(WtsDecoder, MatrixInfoReply) {
  uint8_t pl[12];
  putU16(pl, 0);
  putU16(pl + 2, 6);
  putU16(pl + 4, 14);
  putU16(pl + 6, 340);
  putU16(pl + 8, 340);
  putU16(pl + 10, 4095);
  MatrixInfo mi;
  ASSERT_TRUE(decodeMatrixInfo(PacketView{0x30, pl, 12}, mi));
  EXPECT_EQ(mi.res_x, 6);
  EXPECT_EQ(mi.res_y, 14);
  EXPECT_NEAR(mi.cell_width, 0.0034, 1e-12);
  EXPECT_EQ(mi.full_scale, 4095);
  EXPECT_FALSE(decodeMatrixInfo(PacketView{0x30, pl, 11}, mi));
  putU16(pl, 3);
  EXPECT_FALSE(decodeMatrixInfo(PacketView{0x30, pl, 12}, mi));
}

TEST(WtsDecoder, CalibratedToNewtonsAtTheRightTaxel) {
  // device cell (x=4, y=11) pressed -> {s} (r=4, c=11); linear 2 N / 1000 counts
  FrameDecoder d;
  ASSERT_TRUE(d.configure(CellMapParams{}).ok());
  uint16_t dev_s[84] = {};
  dev_s[4 * 14 + 11] = 1500;
  const auto pkt = framePacket(d.map(), dev_s, 0, false);
  // check the wire order independently: the cell sits at device index y*6+x = 70
  EXPECT_EQ(getU16(pkt.data() + kHeaderLen + 5 + 2 * 70), 1500);
  Parser p;
  p.feed(pkt.data(), pkt.size());
  PacketView v;
  ASSERT_EQ(p.next(v), ParseStatus::Packet);
  tactile::RawTactileFrame raw;
  ASSERT_EQ(d.decode(v, raw), FrameStatus::Ok);
  tactile::Calibration cal;
  tactile::CalibrationParams cp;  // default: c1 = 0.002 N/count
  ASSERT_TRUE(cal.configure(cp).ok());
  tactile::TactileFrame tf;
  ASSERT_EQ(cal.step(raw, tf), tactile::CalibrationStatus::Ok);
  // tolerance: exact arithmetic on a small integer times 0.002, 1e-12 N
  EXPECT_NEAR(tf.at(4, 11), 3.0, 1e-12);
  double sum = 0;
  for (int i = 0; i < 84; ++i) sum += tf.force[static_cast<std::size_t>(i)];
  EXPECT_NEAR(sum, 3.0, 1e-12);
}

// ---- allocation-free per-byte / per-frame path ------------------------------------

TEST(WtsAlloc, ParseAndDecodeDoNotAllocate) {
  FrameDecoder d;
  ASSERT_TRUE(d.configure(CellMapParams{}).ok());
  std::vector<uint8_t> stream;
  for (int k = 0; k < 50; ++k) {
    uint16_t s[84];
    blobFrame(6, 14, k % 6, k % 14, s);
    auto pkt = framePacket(d.map(), s, static_cast<uint32_t>(k), k % 2 == 0);
    if (k % 5 == 0) pkt[20] ^= 0x10;  // some CRC errors
    stream.insert(stream.end(), pkt.begin(), pkt.end());
    stream.push_back(0xAA);  // and garbage
  }
  Parser p;
  tactile::RawTactileFrame f;
  int frames = 0;
  {
    tactile::test::AllocationScope scope;
    for (std::size_t off = 0; off < stream.size();) {
      const std::size_t n = std::min<std::size_t>(37, stream.size() - off);
      std::size_t t = 0;
      while (t < n) {
        t += p.feed(stream.data() + off + t, n - t);
        PacketView v;
        ParseStatus st;
        while ((st = p.next(v)) != ParseStatus::NeedMore)
          if (st == ParseStatus::Packet && d.decode(v, f) == FrameStatus::Ok) ++frames;
      }
      off += n;
    }
    EXPECT_EQ(scope.count(), 0u);
  }
  EXPECT_EQ(frames, 40);
}

// ---- fuzz smoke (the real libFuzzer run is scripts/tools/fuzz_wts.sh) -----------------

TEST(WtsFuzzSmoke, RandomAndMutatedBytesNeverBreakTheParser) {
  FrameDecoder d;
  ASSERT_TRUE(d.configure(CellMapParams{}).ok());
  uint16_t s[84];
  blobFrame(6, 14, 3, 6, s);
  const auto good = framePacket(d.map(), s, 99, false);
  const auto good_rle = framePacket(d.map(), s, 98, true);
  std::mt19937 rng(12345);  // deterministic
  const int kCases = 20000;
  int packets = 0, ok_frames = 0, recovered = 0;
  for (int it = 0; it < kCases; ++it) {
    std::vector<uint8_t> bytes;
    const int mode = it % 4;
    if (mode == 0) {  // pure noise, biased towards the preamble byte
      const int n = static_cast<int>(rng() % 600);
      for (int i = 0; i < n; ++i) bytes.push_back(rng() % 3 == 0 ? 0xAA : static_cast<uint8_t>(rng()));
    } else if (mode == 3) {  // CRC-valid packets with mutated contents: exercises the decoder
      std::vector<uint8_t> pl((it % 2 ? good : good_rle).begin() + kHeaderLen,
                              (it % 2 ? good : good_rle).end() - kCrcLen);
      const int muts = 1 + static_cast<int>(rng() % 6);
      for (int k = 0; k < muts && !pl.empty(); ++k) {
        const std::size_t i = rng() % pl.size();
        switch (rng() % 3) {
          case 0: pl[i] = static_cast<uint8_t>(rng()); break;
          case 1: pl.erase(pl.begin() + static_cast<std::ptrdiff_t>(i)); break;
          case 2: pl.resize(i); break;
        }
      }
      bytes.resize(pl.size() + kOverhead);
      bytes.resize(encodePacket(rng() % 2 ? 0x00 : 0x20, pl.data(), pl.size(), bytes.data(), bytes.size()));
    } else {  // mutated good packets: flips, deletions, insertions, truncation, splices
      bytes = (it % 2) ? good : good_rle;
      const int muts = 1 + static_cast<int>(rng() % 8);
      for (int k = 0; k < muts && !bytes.empty(); ++k) {
        const std::size_t i = rng() % bytes.size();
        switch (rng() % 5) {
          case 0: bytes[i] = static_cast<uint8_t>(bytes[i] ^ (1u << (rng() % 8))); break;
          case 1: bytes.erase(bytes.begin() + static_cast<std::ptrdiff_t>(i)); break;
          case 2: bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(i), static_cast<uint8_t>(rng())); break;
          case 3: bytes.resize(i); break;
          case 4: bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(i), good.begin(), good.begin() + 6); break;
        }
      }
    }
    Parser p(it % 3 == 0 ? Direction::Any : Direction::FromDevice);  // both filters
    tactile::RawTactileFrame f;
    const std::size_t chunk = 1 + rng() % 200;
    for (std::size_t off = 0; off < bytes.size();) {
      const std::size_t n = std::min(chunk, bytes.size() - off);
      std::size_t t = 0;
      while (t < n) {
        t += p.feed(bytes.data() + off + t, n - t);
        PacketView v;
        ParseStatus st;
        int guard = 0;
        while ((st = p.next(v)) != ParseStatus::NeedMore) {
          ASSERT_LT(++guard, 100000) << "parser made no progress, case " << it;
          ASSERT_TRUE(st == ParseStatus::Packet || st == ParseStatus::CrcError || st == ParseStatus::Oversize ||
                      st == ParseStatus::BadHeader);
          if (st == ParseStatus::Packet) {
            ++packets;
            const FrameStatus fs = d.decode(v, f);
            ASSERT_LE(static_cast<int>(fs), static_cast<int>(FrameStatus::NotConfigured));
            if (fs == FrameStatus::Ok) {
              ++ok_frames;
              for (int i = 0; i < 84; ++i) ASSERT_LE(f.counts[static_cast<std::size_t>(i)], kFullScale);
            }
          }
        }
      }
      off += n;
    }
    // after any garbage, a good frame (behind at most one max-size packet of
    // filler, which completes any false header) must decode exactly
    std::vector<uint8_t> filler(kMaxPacket, 0x00);
    std::vector<uint8_t> tail = filler;
    tail.insert(tail.end(), good.begin(), good.end());
    bool found = false;
    std::size_t t = 0;
    while (t < tail.size()) {
      t += p.feed(tail.data() + t, tail.size() - t);
      PacketView v;
      ParseStatus st;
      while ((st = p.next(v)) != ParseStatus::NeedMore)
        if (st == ParseStatus::Packet && d.decode(v, f) == FrameStatus::Ok && f.device_time_ms == 99 &&
            std::equal(s, s + 84, f.counts.begin()))
          found = true;
    }
    recovered += found ? 1 : 0;
  }
  EXPECT_EQ(recovered, kCases);
  EXPECT_GT(packets, 0);  // some mutations leave a valid packet: the decoder path is exercised
  EXPECT_GT(ok_frames, 0);
  std::printf("[fuzz smoke] %d cases, %d CRC-valid packets, %d decoded frames, %d/%d recoveries\n", kCases, packets,
              ok_frames, recovered, kCases);
}
