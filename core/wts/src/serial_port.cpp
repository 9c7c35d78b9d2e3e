#include "tactile_wts/serial_port.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>

namespace tactile {
namespace wts {

namespace {
bool isUnplug(int err) { return err == EIO || err == ENXIO || err == ENODEV || err == EBADF || err == EPIPE; }

long long monoMs() {  // transport-internal deadline clock (not a core: allowed)
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<long long>(ts.tv_sec) * 1000 + ts.tv_nsec / 1000000;
}
}  // namespace

const char* toString(IoStatus s) {
  switch (s) {
    case IoStatus::Ok: return "Ok";
    case IoStatus::Timeout: return "Timeout";
    case IoStatus::Disconnected: return "Disconnected";
    case IoStatus::NotOpen: return "NotOpen";
    case IoStatus::OpenFailed: return "OpenFailed";
    case IoStatus::IoError: return "IoError";
  }
  return "?";
}

SerialPort::~SerialPort() { close(); }

void SerialPort::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

IoStatus SerialPort::fail(int err) {
  errno_ = err;
  if (isUnplug(err)) {
    close();
    return IoStatus::Disconnected;
  }
  return IoStatus::IoError;
}

IoStatus SerialPort::open(const char* path) {
  if (path == nullptr || std::strlen(path) >= path_.size()) {
    errno_ = ENAMETOOLONG;
    return IoStatus::OpenFailed;
  }
  if (path != path_.data()) std::strncpy(path_.data(), path, path_.size() - 1);
  return reopen();
}

IoStatus SerialPort::reopen() {
  close();
  if (path_[0] == '\0') return IoStatus::OpenFailed;
  const int fd = ::open(path_.data(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    errno_ = errno;
    return IoStatus::OpenFailed;
  }
  termios tio{};
  if (tcgetattr(fd, &tio) != 0) {
    errno_ = errno;
    ::close(fd);
    return IoStatus::OpenFailed;
  }
  cfmakeraw(&tio);                 // raw: no echo, no canonical mode, no signals, 8 bit
  tio.c_cflag &= ~static_cast<tcflag_t>(PARENB | CSTOPB | CSIZE | CRTSCTS);
  tio.c_cflag |= CS8 | CLOCAL | CREAD;  // 8N1, ignore modem lines
  tio.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  cfsetispeed(&tio, B115200);
  cfsetospeed(&tio, B115200);
  if (tcsetattr(fd, TCSANOW, &tio) != 0) {
    errno_ = errno;
    ::close(fd);
    return IoStatus::OpenFailed;
  }
  tcflush(fd, TCIOFLUSH);
  fd_ = fd;
  errno_ = 0;
  return IoStatus::Ok;
}

IoStatus SerialPort::read(uint8_t* buf, std::size_t cap, int timeout_ms, std::size_t& got) {
  got = 0;
  if (fd_ < 0) return IoStatus::NotOpen;
  pollfd pfd{fd_, POLLIN, 0};
  int pr;
  do {
    pr = ::poll(&pfd, 1, timeout_ms < 0 ? 0 : timeout_ms);
  } while (pr < 0 && errno == EINTR);
  if (pr < 0) return fail(errno);
  if (pr == 0) return IoStatus::Timeout;
  if ((pfd.revents & POLLIN) == 0 && (pfd.revents & (POLLHUP | POLLERR | POLLNVAL))) return fail(EIO);
  const ssize_t n = ::read(fd_, buf, cap);
  if (n > 0) {
    got = static_cast<std::size_t>(n);
    return IoStatus::Ok;
  }
  if (n == 0) return fail(EIO);  // EOF on a tty: the other side went away
  if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return IoStatus::Timeout;
  return fail(errno);
}

IoStatus SerialPort::write(const uint8_t* buf, std::size_t n, int timeout_ms) {
  if (fd_ < 0) return IoStatus::NotOpen;
  const long long deadline = monoMs() + (timeout_ms < 0 ? 0 : timeout_ms);
  std::size_t done = 0;
  while (done < n) {
    const ssize_t w = ::write(fd_, buf + done, n - done);
    if (w > 0) {
      done += static_cast<std::size_t>(w);
      continue;
    }
    if (w < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) return fail(errno);
    const long long left = deadline - monoMs();
    if (left <= 0) return IoStatus::Timeout;
    pollfd pfd{fd_, POLLOUT, 0};
    const int pr = ::poll(&pfd, 1, static_cast<int>(left));
    if (pr < 0 && errno != EINTR) return fail(errno);
    if (pr > 0 && (pfd.revents & (POLLHUP | POLLERR | POLLNVAL))) return fail(EIO);
  }
  return IoStatus::Ok;
}

}  // namespace wts
}  // namespace tactile
