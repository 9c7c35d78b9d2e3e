#include "tactile_fri/udp.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace tactile {
namespace fri {

const char* toString(UdpStatus s) {
  switch (s) {
    case UdpStatus::Ok: return "ok";
    case UdpStatus::Timeout: return "timeout";
    case UdpStatus::Truncated: return "truncated";
    case UdpStatus::NoPeer: return "no_peer";
    case UdpStatus::WouldBlock: return "would_block";
    case UdpStatus::Error: return "error";
    case UdpStatus::NotOpen: return "not_open";
  }
  return "unknown";
}

sockaddr_in loopbackAddress(uint16_t port) noexcept {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return a;
}

UdpSocket::~UdpSocket() { close(); }

void UdpSocket::close() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  local_port_ = 0;
  has_peer_ = false;
}

ConfigResult UdpSocket::open(const UdpParams& p) {
  close();
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(p.port);
  if (::inet_pton(AF_INET, p.bind_address.c_str(), &addr.sin_addr) != 1)
    return rangeError("fri.udp.bind_address", p.bind_address, "must be a dotted IPv4 address");
  if (p.receive_buffer_bytes < 0)
    return rangeError("fri.udp.receive_buffer_bytes", p.receive_buffer_bytes, "must be >= 0 (0 = default)");
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return ConfigResult::failure(std::string("fri.udp: socket(): ") + std::strerror(errno));
  if (p.receive_buffer_bytes > 0) {
    const int v = p.receive_buffer_bytes;
    ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &v, sizeof v);
  }
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    const int e = errno;
    ::close(fd);
    return ConfigResult::failure("fri.udp: bind(" + p.bind_address + ":" + std::to_string(p.port) +
                                 "): " + std::strerror(e) + " (port must be free, in [0, 65535])");
  }
  sockaddr_in bound{};
  socklen_t len = sizeof bound;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &len);
  fd_ = fd;
  local_port_ = ntohs(bound.sin_port);
  has_peer_ = false;
  return ConfigResult::success();
}

UdpStatus UdpSocket::receive(uint8_t* buf, std::size_t capacity, std::size_t& size, int64_t timeout_us) noexcept {
  size = 0;
  if (fd_ < 0) return UdpStatus::NotOpen;
  pollfd pfd{fd_, POLLIN, 0};
  if (timeout_us < 0) timeout_us = 0;
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(timeout_us / 1000000);
  ts.tv_nsec = static_cast<long>((timeout_us % 1000000) * 1000);
  const int r = ::ppoll(&pfd, 1, &ts, nullptr);
  if (r == 0) return UdpStatus::Timeout;
  if (r < 0) {
    errno_ = errno;
    return errno_ == EINTR ? UdpStatus::Timeout : UdpStatus::Error;
  }
  sockaddr_in from{};
  socklen_t len = sizeof from;
  // MSG_TRUNC: the return value is the datagram's real length even when cut.
  const ssize_t n = ::recvfrom(fd_, buf, capacity, MSG_TRUNC, reinterpret_cast<sockaddr*>(&from), &len);
  if (n < 0) {
    errno_ = errno;
    return (errno_ == EAGAIN || errno_ == EWOULDBLOCK || errno_ == EINTR) ? UdpStatus::Timeout : UdpStatus::Error;
  }
  size = static_cast<std::size_t>(n);
  peer_ = from;
  has_peer_ = true;
  return size > capacity ? UdpStatus::Truncated : UdpStatus::Ok;
}

std::size_t UdpSocket::discardPending(std::size_t max) noexcept {
  if (fd_ < 0) return 0;
  std::size_t dropped = 0;
  uint8_t byte = 0;
  // MSG_DONTWAIT: never blocks; a 1-byte buffer drops the whole datagram (UDP).
  while (dropped < max && ::recv(fd_, &byte, 1, MSG_DONTWAIT | MSG_TRUNC) >= 0) ++dropped;
  return dropped;
}

UdpStatus UdpSocket::sendTo(const sockaddr_in& to, const uint8_t* buf, std::size_t size) noexcept {
  if (fd_ < 0) return UdpStatus::NotOpen;
  const ssize_t n = ::sendto(fd_, buf, size, MSG_DONTWAIT | MSG_NOSIGNAL, reinterpret_cast<const sockaddr*>(&to),
                             sizeof to);
  if (n < 0) {
    errno_ = errno;
    return (errno_ == EAGAIN || errno_ == EWOULDBLOCK) ? UdpStatus::WouldBlock : UdpStatus::Error;
  }
  return UdpStatus::Ok;
}

UdpStatus UdpSocket::reply(const uint8_t* buf, std::size_t size) noexcept {
  if (!has_peer_) return UdpStatus::NoPeer;
  return sendTo(peer_, buf, size);
}

}  // namespace fri
}  // namespace tactile
