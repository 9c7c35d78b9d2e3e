// POSIX UDP transport for FRI. The remote side is paced by the robot: it waits
// (poll, bounded timeout) for the KRC's measurement datagram and replies to the
// sender's address. open() may allocate (it returns a ConfigResult); after it,
// receive()/reply()/sendTo() do not allocate, do not throw, do not log and never
// block longer than the timeout given (sends are non-blocking).
#pragma once

#include <netinet/in.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "tactile_fri/protocol.hpp"
#include "tactile_types/config_result.hpp"

namespace tactile {
namespace fri {

struct UdpParams {
  std::string bind_address = "0.0.0.0";  ///< IPv4 address to bind; tests use 127.0.0.1
  uint16_t port = kDefaultPort;          ///< 0 = ephemeral (read back with localPort())
  int receive_buffer_bytes = 0;          ///< SO_RCVBUF, 0 = system default
};

enum class UdpStatus : uint8_t {
  Ok = 0,
  Timeout = 1,     ///< nothing arrived within the timeout
  Truncated = 2,   ///< datagram larger than the buffer; `size` holds its real length, data cut
  NoPeer = 3,      ///< reply() before any datagram was received
  WouldBlock = 4,  ///< send buffer full: datagram not sent
  Error = 5,       ///< socket error (errno kept in lastErrno())
  NotOpen = 6
};
const char* toString(UdpStatus s);

class UdpSocket {
 public:
  UdpSocket() = default;
  ~UdpSocket();
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  ConfigResult open(const UdpParams& params);
  void close() noexcept;
  bool isOpen() const noexcept { return fd_ >= 0; }
  uint16_t localPort() const noexcept { return local_port_; }
  /// The socket's file descriptor (-1 when closed), for an event loop to wait
  /// on (e.g. RTT's FileDescriptorActivity); the socket stays non-blocking, read
  /// it with receive(..., 0). Owned by this object: stop watching before close().
  int fd() const noexcept { return fd_; }

  /// Wait up to timeout_us microseconds (0 = poll once) for one datagram; on
  /// Ok/Truncated `size` is the datagram's length and its sender becomes the
  /// reply peer.
  UdpStatus receive(uint8_t* buf, std::size_t capacity, std::size_t& size, int64_t timeout_us) noexcept;
  /// Read and drop the datagrams already queued (at most `max`), without
  /// waiting; returns how many were dropped. The reply peer is kept unchanged.
  std::size_t discardPending(std::size_t max = 4096) noexcept;
  /// Send to the sender of the last received datagram.
  UdpStatus reply(const uint8_t* buf, std::size_t size) noexcept;
  /// Send to an explicit IPv4 address (used by the simulated KRC).
  UdpStatus sendTo(const sockaddr_in& to, const uint8_t* buf, std::size_t size) noexcept;

  const sockaddr_in& lastPeer() const noexcept { return peer_; }
  bool hasPeer() const noexcept { return has_peer_; }
  int lastErrno() const noexcept { return errno_; }

 private:
  int fd_ = -1;
  uint16_t local_port_ = 0;
  sockaddr_in peer_{};
  bool has_peer_ = false;
  int errno_ = 0;
};

/// 127.0.0.1:port
sockaddr_in loopbackAddress(uint16_t port) noexcept;

}  // namespace fri
}  // namespace tactile
