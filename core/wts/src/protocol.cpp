#include "tactile_wts/protocol.hpp"

#include <cstring>
#include <string>

namespace tactile {
namespace wts {

namespace {

// CRC-CCITT lookup table (polynomial 0x1021, MSB-first table as in the public
// WTS drivers), computed at compile time.
struct CrcTable {
  std::array<uint16_t, 256> t{};
  constexpr CrcTable() {
    for (int i = 0; i < 256; ++i) {
      uint16_t c = static_cast<uint16_t>(i << 8);
      for (int k = 0; k < 8; ++k) c = static_cast<uint16_t>((c & 0x8000) ? ((c << 1) ^ 0x1021) : (c << 1));
      t[static_cast<std::size_t>(i)] = c;
    }
  }
};
constexpr CrcTable kCrc;
static_assert(kCrc.t[1] == 0x1021 && kCrc.t[255] == 0x1EF0, "CRC-CCITT table");

}  // namespace

uint16_t crc16(const uint8_t* data, std::size_t n, uint16_t crc) {
  for (std::size_t i = 0; i < n; ++i) crc = static_cast<uint16_t>(kCrc.t[(crc ^ data[i]) & 0xFF] ^ (crc >> 8));
  return crc;
}

const char* toString(StatusCode s) {
  static const char* const names[] = {
      "E_SUCCESS", "E_NOT_AVAILABLE", "E_NO_SENSOR", "E_NOT_INITIALIZED", "E_ALREADY_RUNNING",
      "E_FEATURE_NOT_SUPPORTED", "E_INCONSISTENT_DATA", "E_TIMEOUT", "E_READ_ERROR", "E_WRITE_ERROR",
      "E_INSUFFICIENT_RESOURCES", "E_CHECKSUM_ERROR", "E_NO_PARAM_EXPECTED", "E_NOT_ENOUGH_PARAMS",
      "E_CMD_UNKNOWN", "E_CMD_FORMAT_ERROR", "E_ACCESS_DENIED", "E_ALREADY_OPEN", "E_CMD_FAILED",
      "E_CMD_ABORTED", "E_INVALID_HANDLE", "E_NOT_FOUND", "E_NOT_OPEN", "E_IO_ERROR", "E_INVALID_PARAMETER",
      "E_INDEX_OUT_OF_BOUNDS", "E_CMD_PENDING", "E_OVERRUN", "E_RANGE_ERROR", "E_AXIS_BLOCKED",
      "E_FILE_EXISTS"};
  const auto v = static_cast<uint16_t>(s);
  return v < sizeof(names) / sizeof(names[0]) ? names[v] : "E_UNKNOWN";
}

const char* commandName(uint8_t id) {
  switch (static_cast<Command>(id)) {
    case Command::FrameData: return "frame data";
    case Command::Loop: return "loop";
    case Command::ReadSingleFrame: return "read single frame";
    case Command::StartPeriodic: return "start periodic";
    case Command::StopPeriodic: return "stop periodic";
    case Command::Tare: return "tare";
    case Command::MatrixInfo: return "matrix info";
    case Command::SensorType: return "sensor type";
    case Command::Temperature: return "temperature";
    case Command::SystemInfo: return "system info";
  }
  return "unknown";
}

const char* toString(ParseStatus s) {
  switch (s) {
    case ParseStatus::NeedMore: return "NeedMore";
    case ParseStatus::Packet: return "Packet";
    case ParseStatus::CrcError: return "CrcError";
    case ParseStatus::Oversize: return "Oversize";
    case ParseStatus::BadHeader: return "BadHeader";
  }
  return "?";
}

const char* toString(FrameStatus s) {
  switch (s) {
    case FrameStatus::Ok: return "Ok";
    case FrameStatus::NotAFrame: return "NotAFrame";
    case FrameStatus::DeviceError: return "DeviceError";
    case FrameStatus::BadSize: return "BadSize";
    case FrameStatus::BadRle: return "BadRle";
    case FrameStatus::OutOfRange: return "OutOfRange";
    case FrameStatus::NotConfigured: return "NotConfigured";
  }
  return "?";
}

// ---- encoding ----------------------------------------------------------------

std::size_t encodePacket(uint8_t id, const uint8_t* payload, std::size_t size, uint8_t* out, std::size_t cap) {
  if (size > kMaxPayload || cap < size + kOverhead || (size > 0 && payload == nullptr)) return 0;
  out[0] = out[1] = out[2] = kPreambleByte;
  out[3] = id;
  putU16(out + 4, static_cast<uint16_t>(size));
  if (size > 0) std::memmove(out + kHeaderLen, payload, size);
  putU16(out + kHeaderLen + size, crc16(out, kHeaderLen + size));
  return size + kOverhead;
}

std::size_t encodeReadSingleFrame(bool rle, uint8_t* out, std::size_t cap) {
  const uint8_t p[1] = {static_cast<uint8_t>(rle ? kFlagRle : 0)};
  return encodePacket(static_cast<uint8_t>(Command::ReadSingleFrame), p, 1, out, cap);
}

std::size_t encodeStartPeriodic(bool rle, uint16_t delay_ms, uint8_t* out, std::size_t cap) {
  uint8_t p[3] = {static_cast<uint8_t>(rle ? kFlagRle : 0), 0, 0};
  putU16(p + 1, delay_ms);
  return encodePacket(static_cast<uint8_t>(Command::StartPeriodic), p, 3, out, cap);
}

std::size_t encodeStopPeriodic(uint8_t* out, std::size_t cap) { return encodeSimple(Command::StopPeriodic, out, cap); }

std::size_t encodeTare(bool tare, uint8_t* out, std::size_t cap) {
  const uint8_t p[1] = {static_cast<uint8_t>(tare ? 1 : 0)};
  return encodePacket(static_cast<uint8_t>(Command::Tare), p, 1, out, cap);
}

std::size_t encodeSimple(Command c, uint8_t* out, std::size_t cap) {
  return encodePacket(static_cast<uint8_t>(c), nullptr, 0, out, cap);
}

std::size_t encodeCells(const uint16_t* cells, int n, bool rle, uint8_t* out, std::size_t cap) {
  std::size_t w = 0;
  if (n < 0) return 0;
  if (!rle) {
    if (cap < 2 * static_cast<std::size_t>(n)) return 0;
    for (int i = 0; i < n; ++i, w += 2) putU16(out + w, static_cast<uint16_t>(cells[i] & 0x0FFF));
    return w;
  }
  int i = 0;
  while (i < n) {
    const uint16_t v = static_cast<uint16_t>(cells[i] & 0x0FFF);
    int run = 1;
    while (i + run < n && run < 15 && (cells[i + run] & 0x0FFF) == v) ++run;
    if (w + 2 > cap) return 0;
    putU16(out + w, static_cast<uint16_t>(v | (run << 12)));
    w += 2;
    i += run;
  }
  return w;
}

// ---- parser --------------------------------------------------------------------

bool plausibleHeader(Direction d, uint8_t id, uint16_t size, int max_cells) {
  if (size > kMaxPayload) return false;
  if (max_cells < 1 || max_cells > kMaxTaxels) max_cells = kMaxTaxels;
  const int kCells2 = 2 * max_cells;
  switch (d) {
    case Direction::Any:
      return true;
    case Direction::FromDevice:
      switch (static_cast<Command>(id)) {
        case Command::FrameData: return size >= 5 && size <= 5 + kCells2;
        case Command::ReadSingleFrame: return size == 2 || (size >= 7 && size <= 7 + kCells2);
        case Command::Loop: return size >= 2;
        case Command::StartPeriodic:
        case Command::StopPeriodic:
        case Command::Tare:
        case Command::Temperature: return size >= 2 && size <= 16;
        case Command::MatrixInfo: return size >= 2 && size <= 32;
        case Command::SensorType:
        case Command::SystemInfo: return size >= 2 && size <= 128;
      }
      return false;
  }
  return false;
}

void Parser::reset() {
  start_ = len_ = pending_consume_ = 0;
}

void Parser::compact() {
  if (start_ == 0) return;
  const std::size_t n = len_ - start_;
  if (n > 0) std::memmove(buf_.data(), buf_.data() + start_, n);
  start_ = 0;
  len_ = n;
}

std::size_t Parser::feed(const uint8_t* data, std::size_t n) {
  if (pending_consume_) {
    start_ += pending_consume_;
    pending_consume_ = 0;
  }
  if (data == nullptr || n == 0) return 0;
  if (len_ + n > buf_.size()) compact();
  const std::size_t take = n < buf_.size() - len_ ? n : buf_.size() - len_;
  std::memcpy(buf_.data() + len_, data, take);
  len_ += take;
  return take;
}

ParseStatus Parser::next(PacketView& out) {
  if (pending_consume_) {
    start_ += pending_consume_;
    pending_consume_ = 0;
  }
  while (true) {
    // 1. find the preamble AA AA AA
    std::size_t i = start_;
    while (i + kPreambleLen <= len_ &&
           !(buf_[i] == kPreambleByte && buf_[i + 1] == kPreambleByte && buf_[i + 2] == kPreambleByte))
      ++i;
    if (i + kPreambleLen > len_) {
      // keep a possible partial preamble (up to 2 trailing AA bytes)
      std::size_t keep = 0;
      while (keep < 2 && keep < len_ - start_ && buf_[len_ - 1 - keep] == kPreambleByte) ++keep;
      stats_.skipped_bytes += (len_ - start_) - keep;
      start_ = len_ - keep;
      if (start_ == len_) start_ = len_ = 0;
      return ParseStatus::NeedMore;
    }
    stats_.skipped_bytes += i - start_;
    start_ = i;
    // 2. header
    if (len_ - start_ < kHeaderLen) return ParseStatus::NeedMore;
    const uint16_t size = getU16(&buf_[start_ + 4]);
    if (size > kMaxPayload) {
      ++stats_.oversize;
      ++start_;  // resync from the next byte
      return ParseStatus::Oversize;
    }
    if (!plausibleHeader(dir_, buf_[start_ + 3], size, max_cells_)) {
      ++stats_.bad_headers;
      ++start_;
      return ParseStatus::BadHeader;
    }
    const std::size_t total = kHeaderLen + size + kCrcLen;
    if (len_ - start_ < total) return ParseStatus::NeedMore;
    // 3. CRC (Eq.-free: protocol CRC-CCITT, see protocol.hpp)
    const uint16_t want = getU16(&buf_[start_ + kHeaderLen + size]);
    if (crc16(&buf_[start_], kHeaderLen + size) != want) {
      ++stats_.crc_errors;
      ++start_;
      return ParseStatus::CrcError;
    }
    out.id = buf_[start_ + 3];
    out.size = size;
    out.payload = &buf_[start_ + kHeaderLen];
    pending_consume_ = total;
    ++stats_.packets;
    return ParseStatus::Packet;
  }
}

// ---- cell map ------------------------------------------------------------------

ConfigResult CellMap::configure(const CellMapParams& p) {
  if (p.rows < 1 || p.rows > kMaxRows)
    return rangeError("wts.rows", p.rows, "must be in [1, " + std::to_string(kMaxRows) + "]");
  if (p.cols < 1 || p.cols > kMaxCols)
    return rangeError("wts.cols", p.cols, "must be in [1, " + std::to_string(kMaxCols) + "]");
  p_ = p;
  res_x_ = p.transpose ? p.rows : p.cols;
  res_y_ = p.transpose ? p.cols : p.rows;
  for (int y = 0; y < res_y_; ++y) {
    for (int x = 0; x < res_x_; ++x) {
      int r = p.transpose ? x : y;
      int c = p.transpose ? y : x;
      if (p.flip_rows) r = p.rows - 1 - r;
      if (p.flip_cols) c = p.cols - 1 - c;
      const int k = y * res_x_ + x;
      const int i = r * p.cols + c;
      dev_to_s_[static_cast<std::size_t>(k)] = static_cast<uint16_t>(i);
      s_to_dev_[static_cast<std::size_t>(i)] = static_cast<uint16_t>(k);
    }
  }
  return ConfigResult::success();
}

// ---- frame decoding ------------------------------------------------------------

ConfigResult FrameDecoder::configure(const CellMapParams& p) {
  configured_ = false;
  ConfigResult r = map_.configure(p);
  if (!r) return r;
  configured_ = true;
  return r;
}

FrameStatus FrameDecoder::decode(const PacketView& pkt, RawTactileFrame& out) {
  if (!configured_) return FrameStatus::NotConfigured;
  const uint8_t* p = pkt.payload;
  std::size_t n = pkt.size;
  if (pkt.id == static_cast<uint8_t>(Command::ReadSingleFrame)) {
    if (n < 2) return FrameStatus::BadSize;
    device_status_ = static_cast<StatusCode>(getU16(p));
    if (device_status_ != StatusCode::Success) return FrameStatus::DeviceError;
    p += 2;
    n -= 2;
  } else if (pkt.id != static_cast<uint8_t>(Command::FrameData)) {
    return FrameStatus::NotAFrame;
  }
  if (n < 5 || p == nullptr) return FrameStatus::BadSize;
  const uint32_t t_ms = getU32(p);
  const bool rle = (p[4] & kFlagRle) != 0;
  p += 5;
  n -= 5;
  const int cells = map_.cells();
  if (!rle) {
    if (n != 2 * static_cast<std::size_t>(cells)) return FrameStatus::BadSize;
    for (int k = 0; k < cells; ++k) {
      const uint16_t u = getU16(p + 2 * k);
      if (u > kFullScale) return FrameStatus::OutOfRange;
      scratch_[map_.toSensing(k)] = u;
    }
  } else {
    if (n % 2 != 0 || n > 2 * static_cast<std::size_t>(cells)) return FrameStatus::BadSize;
    int k = 0;
    for (std::size_t j = 0; j < n; j += 2) {
      const uint16_t u = getU16(p + j);
      const uint16_t v = static_cast<uint16_t>(u & 0x0FFF);
      const int run = u >> 12;
      if (k + run > cells) return FrameStatus::BadRle;
      for (int m = 0; m < run; ++m) scratch_[map_.toSensing(k++)] = v;
    }
    if (k != cells) return FrameStatus::BadRle;
  }
  out.device_time_ms = t_ms;
  out.rows = static_cast<uint16_t>(map_.params().rows);
  out.cols = static_cast<uint16_t>(map_.params().cols);
  std::memcpy(out.counts.data(), scratch_.data(), sizeof(uint16_t) * static_cast<std::size_t>(cells));
  return FrameStatus::Ok;
}

bool decodeMatrixInfo(const PacketView& pkt, MatrixInfo& out) {
  StatusCode s;
  if (pkt.id != static_cast<uint8_t>(Command::MatrixInfo) || pkt.size < 12 || !pkt.status(s) ||
      s != StatusCode::Success)
    return false;
  out.res_x = getU16(pkt.payload + 2);
  out.res_y = getU16(pkt.payload + 4);
  out.cell_width = getU16(pkt.payload + 6) * 1e-5;
  out.cell_height = getU16(pkt.payload + 8) * 1e-5;
  out.full_scale = getU16(pkt.payload + 10);
  return true;
}

}  // namespace wts
}  // namespace tactile
