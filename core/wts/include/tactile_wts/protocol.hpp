// Weiss WTS tactile sensor serial protocol: packet encoder, incremental parser
// with CRC check and resynchronisation, frame decoder (plain and RLE), status
// codes, and the mapping from the device's cell order to the {s} layout.
// RTT-free, exception-free and allocation-free after configure().
//
// WIRE FORMAT (facts from public WTS drivers):
//   packet  = AA AA AA | id (u8) | size (u16 LE) | payload[size] | crc (u16 LE)
//   crc     = CRC-CCITT table (poly 0x1021), start 0xFFFF,
//             crc = T[(crc ^ b) & 0xFF] ^ (crc >> 8), over every byte from the
//             preamble to the end of the payload.
//             e.g. AA AA AA 20 01 00 00 -> CRC bytes 8F 83.
//   replies to a command carry the command's id and start with a u16 status code
//   (StatusCode below). Exception: periodic frames (id 0x00) carry no status.
//
// FRAME PAYLOADS
//   id 0x20 (reply to "read single frame"):
//       status u16 | timestamp u32 (ms) | flags u8 | cells
//   id 0x00 (periodic frame data, after "start periodic" 0x21):
//                    timestamp u32 (ms) | flags u8 | cells
//   flags bit 0 = RLE. Cells are u16 LE:
//     plain: one unit per cell, value = unit & 0x0FFF (12 bit, full scale 4095);
//            a 6x14 single-frame reply is 3+1+2+(2+4+1+168)+2 = 183 bytes.
//     RLE:   each unit carries value = unit & 0x0FFF and a run length
//            count = unit >> 12 (the number of consecutive cells with that value,
//            0..15; a unit with count 0 covers no cell). The runs must cover
//            exactly the number of cells; anything else is BadRle.
//
// CELL ORDER -> {s} LAYOUT (the one place this mapping is defined; CellMap):
//   The device reports its matrix as resolution_x * resolution_y (command 0x30)
//   and sends the cells x-fastest: device index k = y * res_x + x.
//   The {s} layout (conventions.hpp) is row-major, rows along {s} y (6-taxel
//   side), cols along {s} x (14-taxel side): index i = r * cols + c.
//   CellMapParams chooses how device (x, y) lands on {s} (r, c):
//     transpose = false:  r = y, c = x   (device x along the 14-taxel side)
//     transpose = true:   r = x, c = y   (device x along the 6-taxel side)
//     then flip_rows: r -> rows-1-r, flip_cols: c -> cols-1-c.
//   Default for the WTS0614 (rows 6, cols 14): the device names itself "0614",
//   i.e. res_x = 6, res_y = 14, so transpose = true, no flips. The flips depend
//   on how the pad is mounted on the flange and are NOT verified on hardware
//   here: press one corner taxel and check with `wts_read --raw` that the
//   largest value lands where {s} says (row 0 = most negative y, col 0 = most
//   negative x), then set flip_rows / flip_cols.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "tactile_types/config_result.hpp"
#include "tactile_types/types.hpp"

namespace tactile {
namespace wts {

constexpr uint8_t kPreambleByte = 0xAA;
constexpr std::size_t kPreambleLen = 3;
constexpr std::size_t kHeaderLen = kPreambleLen + 1 + 2;  ///< preamble, id, size
constexpr std::size_t kCrcLen = 2;
constexpr std::size_t kOverhead = kHeaderLen + kCrcLen;   ///< 8 bytes around the payload
/// Largest payload accepted: a full kMaxTaxels plain frame with status, plus slack
/// for text replies. Larger sizes are rejected as Oversize (resync).
constexpr std::size_t kMaxPayload = 2 + 4 + 1 + 2 * kMaxTaxels + 64;
constexpr std::size_t kMaxPacket = kMaxPayload + kOverhead;
constexpr uint16_t kFullScale = 4095;
constexpr uint8_t kFlagRle = 0x01;

/// Command / reply ids.
enum class Command : uint8_t {
  FrameData = 0x00,        ///< periodic frame (device -> host), no status
  Loop = 0x06,             ///< echo: the reply returns the payload after the status
  ReadSingleFrame = 0x20,  ///< payload: flags (bit 0 = RLE)
  StartPeriodic = 0x21,    ///< payload: flags (bit 0 = RLE), delay u16 ms
  StopPeriodic = 0x22,
  Tare = 0x23,             ///< payload: u8 1 = tare, 0 = clear tare
  MatrixInfo = 0x30,       ///< reply: status, res_x, res_y, cell_w, cell_h, full scale (MatrixInfo)
  SensorType = 0x38,       ///< reply: status, text
  Temperature = 0x46,      ///< reply: status, i16 in 0.1 degC
  SystemInfo = 0x50,       ///< reply: status, type u8, hw rev u8, fw u16, serial u32
};

/// Status codes (first u16 of every reply), the common Weiss error list.
enum class StatusCode : uint16_t {
  Success = 0, NotAvailable = 1, NoSensor = 2, NotInitialized = 3, AlreadyRunning = 4,
  FeatureNotSupported = 5, InconsistentData = 6, Timeout = 7, ReadError = 8, WriteError = 9,
  InsufficientResources = 10, ChecksumError = 11, NoParamExpected = 12, NotEnoughParams = 13,
  CmdUnknown = 14, CmdFormatError = 15, AccessDenied = 16, AlreadyOpen = 17, CmdFailed = 18,
  CmdAborted = 19, InvalidHandle = 20, NotFound = 21, NotOpen = 22, IoError = 23,
  InvalidParameter = 24, IndexOutOfBounds = 25, CmdPending = 26, Overrun = 27, RangeError = 28,
  AxisBlocked = 29, FileExists = 30
};
/// "E_SUCCESS", "E_CHECKSUM_ERROR", ...; "E_UNKNOWN" for values outside the list.
const char* toString(StatusCode s);
const char* commandName(uint8_t id);

/// CRC of the WTS protocol (see header comment).
uint16_t crc16(const uint8_t* data, std::size_t n, uint16_t crc = 0xFFFF);

inline uint16_t getU16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
inline uint32_t getU32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) | (static_cast<uint32_t>(p[2]) << 16) |
         (static_cast<uint32_t>(p[3]) << 24);
}
inline void putU16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v & 0xFF);
  p[1] = static_cast<uint8_t>(v >> 8);
}
inline void putU32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>((v >> (8 * i)) & 0xFF);
}

/// Writes a complete packet into out[0..cap). Returns its length, or 0 when it
/// does not fit (cap < size + 8) or size > kMaxPayload.
std::size_t encodePacket(uint8_t id, const uint8_t* payload, std::size_t size, uint8_t* out, std::size_t cap);

// Host -> device commands. Each returns the packet length (0 if cap too small).
std::size_t encodeReadSingleFrame(bool rle, uint8_t* out, std::size_t cap);
std::size_t encodeStartPeriodic(bool rle, uint16_t delay_ms, uint8_t* out, std::size_t cap);
std::size_t encodeStopPeriodic(uint8_t* out, std::size_t cap);
std::size_t encodeTare(bool tare, uint8_t* out, std::size_t cap);
std::size_t encodeSimple(Command c, uint8_t* out, std::size_t cap);  ///< any command without payload

/// A complete packet inside the parser's buffer; valid until the next feed()/next().
struct PacketView {
  uint8_t id = 0;
  const uint8_t* payload = nullptr;
  uint16_t size = 0;
  /// Status code of a reply (payload[0..1]); false if the payload is shorter.
  bool status(StatusCode& s) const {
    if (size < 2) return false;
    s = static_cast<StatusCode>(getU16(payload));
    return true;
  }
};

enum class ParseStatus : uint8_t {
  NeedMore = 0,  ///< no complete packet in the buffer
  Packet = 1,    ///< `out` holds a packet whose CRC matched
  CrcError = 2,  ///< a candidate packet failed its CRC; resynchronising
  Oversize = 3,  ///< a candidate header declared size > kMaxPayload; resynchronising
  BadHeader = 4, ///< id unknown or size impossible for that id (direction filter); resynchronising
};

/// Which packets a Parser accepts, checked on the 6-byte header before waiting
/// for the payload, so a false preamble in noise is dropped at once instead of
/// holding back good packets until a bogus size has arrived.
///   Any:        every id, size <= kMaxPayload.
///   FromDevice: replies/frames the WTS sends (what the driver reads):
///               0x00 size 5..5+2*kMaxTaxels; 0x20 size 2 (error) or 7..7+2*kMaxTaxels;
///               0x06 2..kMaxPayload; 0x21/0x22/0x23/0x46 2..16; 0x30 2..32;
///               0x38/0x50 2..128; any other id is rejected.
/// (The simulated device reads commands with Any, so it can answer unknown ids
/// with E_CMD_UNKNOWN like a real device.)
enum class Direction : uint8_t { Any = 0, FromDevice = 1 };
/// `max_cells` bounds the frame sizes (a driver passes its configured rows*cols).
bool plausibleHeader(Direction d, uint8_t id, uint16_t size, int max_cells = kMaxTaxels);
const char* toString(ParseStatus s);

struct ParserStats {
  uint64_t packets = 0;
  uint64_t crc_errors = 0;
  uint64_t oversize = 0;
  uint64_t skipped_bytes = 0;  ///< bytes discarded while looking for a preamble
  uint64_t bad_headers = 0;    ///< headers refused by the direction filter
};

/// Incremental parser. Bytes go in with feed() (any chunking, down to one byte);
/// packets come out of next(). After garbage, a CRC error or an oversize header
/// it drops one byte and rescans, so a good packet hidden behind a false
/// preamble (e.g. after a truncated frame) is still found. Fixed buffer of
/// 2 * kMaxPacket; never allocates.
class Parser {
 public:
  explicit Parser(Direction d = Direction::Any, int max_cells = kMaxTaxels)
      : dir_(d), max_cells_(max_cells < 1 || max_cells > kMaxTaxels ? kMaxTaxels : max_cells) {}
  /// Copies as many bytes as fit; returns how many were taken. Call next()
  /// until NeedMore, then feed the rest.
  std::size_t feed(const uint8_t* data, std::size_t n);
  ParseStatus next(PacketView& out);
  void reset();
  const ParserStats& stats() const { return stats_; }
  std::size_t buffered() const { return len_ - start_; }

 private:
  void compact();
  std::array<uint8_t, 2 * kMaxPacket> buf_{};
  std::size_t start_ = 0, len_ = 0;
  std::size_t pending_consume_ = 0;  ///< bytes of the last returned packet, dropped on the next call
  Direction dir_ = Direction::Any;
  int max_cells_ = kMaxTaxels;
  ParserStats stats_;
};

/// Device -> {s} cell order (see the header comment).
struct CellMapParams {
  int rows = kDefaultRows;  ///< {s} rows (6-taxel side)
  int cols = kDefaultCols;  ///< {s} cols (14-taxel side)
  bool transpose = true;    ///< device x runs along {s} rows (the 6-taxel side)
  bool flip_rows = false;
  bool flip_cols = false;
};

class CellMap {
 public:
  ConfigResult configure(const CellMapParams& p);
  int resX() const { return res_x_; }  ///< device resolution_x implied by the mapping
  int resY() const { return res_y_; }
  int cells() const { return p_.rows * p_.cols; }
  /// {s} row-major index of device cell k (k = y * resX + x).
  uint16_t toSensing(int k) const { return dev_to_s_[static_cast<std::size_t>(k)]; }
  /// Device index of {s} cell i (inverse of toSensing).
  uint16_t toDevice(int i) const { return s_to_dev_[static_cast<std::size_t>(i)]; }
  const CellMapParams& params() const { return p_; }

 private:
  CellMapParams p_;
  int res_x_ = 0, res_y_ = 0;
  std::array<uint16_t, kMaxTaxels> dev_to_s_{};
  std::array<uint16_t, kMaxTaxels> s_to_dev_{};
};

enum class FrameStatus : uint8_t {
  Ok = 0,
  NotAFrame = 1,     ///< packet id is neither 0x00 nor 0x20
  DeviceError = 2,   ///< 0x20 reply with status != Success (see device_status)
  BadSize = 3,       ///< payload size does not match the configured matrix
  BadRle = 4,        ///< RLE runs do not cover exactly rows*cols cells
  OutOfRange = 5,    ///< a plain cell value > 4095 (bits 12..15 set)
  NotConfigured = 6,
};
const char* toString(FrameStatus s);

/// Payload of a frame packet -> RawTactileFrame in the {s} layout.
class FrameDecoder {
 public:
  ConfigResult configure(const CellMapParams& p);
  /// Decodes `pkt` into `out` (counts, rows, cols, device_time_ms). Leaves
  /// `out` untouched unless it returns Ok. Allocation-free.
  FrameStatus decode(const PacketView& pkt, RawTactileFrame& out);
  StatusCode deviceStatus() const { return device_status_; }
  const CellMap& map() const { return map_; }

 private:
  bool configured_ = false;
  CellMap map_;
  std::array<uint16_t, kMaxTaxels> scratch_{};
  StatusCode device_status_ = StatusCode::Success;
};

/// Device-side encoding of frame cells (used by the simulated device, the tests
/// and the benchmarks): `cells` in device order. Returns the number of bytes
/// written to out (0 if cap is too small). RLE splits runs longer than 15.
std::size_t encodeCells(const uint16_t* cells, int n, bool rle, uint8_t* out, std::size_t cap);

/// Matrix information (reply to 0x30).
struct MatrixInfo {
  uint16_t res_x = 0, res_y = 0;
  double cell_width = 0.0, cell_height = 0.0;  ///< m (wire: u16 in units of 10 um)
  uint16_t full_scale = 0;
};
/// False if the packet is not a successful 0x30 reply of at least 12 bytes.
bool decodeMatrixInfo(const PacketView& pkt, MatrixInfo& out);

}  // namespace wts
}  // namespace tactile
