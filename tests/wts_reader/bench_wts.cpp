// Decode time per WTS0614 frame: parser (preamble scan + CRC) + frame decoder
// into a RawTactileFrame in the {s} layout. Plain vs RLE in the same run, for a
// typical sparse contact frame (a pressed blob) and for a dense worst case for
// RLE (every cell different). Also the parser alone and CRC alone.
// Report: BM_*_Rle / BM_*_Plain time ratio from one run.
#include <benchmark/benchmark.h>

#include <vector>

#include "tactile_wts/protocol.hpp"
#include "wts_test_util.hpp"

using namespace tactile::wts;

namespace {

std::vector<uint8_t> makePacket(bool rle, bool dense) {
  CellMap m;
  m.configure(CellMapParams{});
  uint16_t s[84];
  if (dense) {
    for (int i = 0; i < 84; ++i) s[i] = static_cast<uint16_t>((i * 37) % 4096);
  } else {
    wtstest::blobFrame(6, 14, 2, 6, s);
  }
  return wtstest::framePacket(m, s, 1000, rle);
}

void decodeLoop(benchmark::State& state, bool rle, bool dense) {
  const auto pkt = makePacket(rle, dense);
  FrameDecoder d;
  d.configure(CellMapParams{});
  Parser p;
  tactile::RawTactileFrame f;
  for (auto _ : state) {
    p.feed(pkt.data(), pkt.size());
    PacketView v;
    if (p.next(v) != ParseStatus::Packet || d.decode(v, f) != FrameStatus::Ok) state.SkipWithError("decode failed");
    benchmark::DoNotOptimize(f.counts.data());
    benchmark::ClobberMemory();
  }
  state.counters["bytes"] = static_cast<double>(pkt.size());
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(pkt.size()));
}

void BM_DecodeFrame_Contact_Plain(benchmark::State& s) { decodeLoop(s, false, false); }
void BM_DecodeFrame_Contact_Rle(benchmark::State& s) { decodeLoop(s, true, false); }
void BM_DecodeFrame_Dense_Plain(benchmark::State& s) { decodeLoop(s, false, true); }
void BM_DecodeFrame_Dense_Rle(benchmark::State& s) { decodeLoop(s, true, true); }

void BM_ParseOnly_Plain(benchmark::State& state) {
  const auto pkt = makePacket(false, false);
  Parser p;
  for (auto _ : state) {
    p.feed(pkt.data(), pkt.size());
    PacketView v;
    benchmark::DoNotOptimize(p.next(v));
    benchmark::DoNotOptimize(v.payload);
  }
}

void BM_Crc_181B(benchmark::State& state) {
  const auto pkt = makePacket(false, false);
  for (auto _ : state) benchmark::DoNotOptimize(crc16(pkt.data(), pkt.size() - 2));
}

}  // namespace

BENCHMARK(BM_DecodeFrame_Contact_Plain);
BENCHMARK(BM_DecodeFrame_Contact_Rle);
BENCHMARK(BM_DecodeFrame_Dense_Plain);
BENCHMARK(BM_DecodeFrame_Dense_Rle);
BENCHMARK(BM_ParseOnly_Plain);
BENCHMARK(BM_Crc_181B);
