// POSIX serial transport for the WTS (USB CDC ACM, e.g. /dev/ttyACM0):
// termios raw mode, 115200 baud 8N1, no flow control, non-blocking fd with
// poll()-bounded reads and writes. Xenomai-compatible in spirit: open() may
// allocate (path copy) and block briefly; after open() no call allocates, and
// every call returns within its timeout.
//
// Unplug: a read/write/poll that reports EIO, ENXIO, ENODEV, EBADF or POLLHUP /
// POLLERR closes the fd and returns IoStatus::Disconnected; the owner calls
// open() again later (WtsDriver does this at its configured reconnect period).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace tactile {
namespace wts {

enum class IoStatus : uint8_t {
  Ok = 0,
  Timeout = 1,       ///< nothing (or not everything) transferred within the timeout
  Disconnected = 2,  ///< device gone (unplug, hangup, EIO/ENXIO); fd closed
  NotOpen = 3,
  OpenFailed = 4,    ///< open()/termios setup failed; errno in lastErrno()
  IoError = 5,       ///< other errno; the port stays open
};
const char* toString(IoStatus s);

class SerialPort {
 public:
  SerialPort() = default;
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  /// Opens `path` (NUL-terminated, < 256 chars) raw 115200 8N1 and flushes stale input.
  IoStatus open(const char* path);
  /// Re-opens the last path (after Disconnected). Allocation-free.
  IoStatus reopen();
  void close();
  bool isOpen() const { return fd_ >= 0; }
  /// The open file descriptor (-1 when closed), for an event loop to wait on.
  int fd() const { return fd_; }

  /// Reads up to `cap` bytes; waits at most `timeout_ms` for the first byte
  /// (0 = just poll). `got` = bytes read. Ok if got > 0, Timeout if none.
  IoStatus read(uint8_t* buf, std::size_t cap, int timeout_ms, std::size_t& got);
  /// Writes all `n` bytes or gives up after `timeout_ms` in total (Timeout).
  IoStatus write(const uint8_t* buf, std::size_t n, int timeout_ms);
  int lastErrno() const { return errno_; }
  const char* path() const { return path_.data(); }

 private:
  IoStatus fail(int err);
  int fd_ = -1;
  int errno_ = 0;
  std::array<char, 256> path_{};
};

}  // namespace wts
}  // namespace tactile
