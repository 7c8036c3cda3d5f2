// SPDX-License-Identifier: MIT
#pragma once
// A Modbus TCP proxy on 127.0.0.1 that records the order of requests and replies on the wire
// (tests/hil/loop/clock_test): every connection the gateway opens to it is forwarded to the
// plant server's port on a connection of its own, byte for byte, and every whole frame
// (MBAP header + PDU) is recorded, in the order the proxy passed it on, before it is
// forwarded. A reply is recorded before the gateway can have it, a request before the plant
// can: the recorded order is the order of cause and effect.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace excite::test {

class RecordingProxy {
 public:
  struct Frame {
    int connection = 0;    // 0, 1, … in the order the gateway connected
    bool request = false;  // gateway -> plant; false: plant -> gateway
    std::uint16_t transaction = 0;
    std::uint8_t function = 0;  // PDU function code (bit 7 set: an exception reply)
  };

  explicit RecordingProxy(std::uint16_t upstream_port) : upstream_port_(upstream_port) {
    listen_fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a = loopback(0);
    bind(listen_fd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t len = sizeof a;
    getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    listen(listen_fd_, 8);
    acceptor_ = std::thread([this] { accept_loop(); });
  }
  RecordingProxy(const RecordingProxy&) = delete;
  RecordingProxy& operator=(const RecordingProxy&) = delete;
  ~RecordingProxy() {
    stop_ = true;
    shutdown(listen_fd_, SHUT_RDWR);
    close(listen_fd_);
    acceptor_.join();
    for (std::thread& t : links_) t.join();
  }

  std::uint16_t port() const { return port_; }

  /// The link cut (true) and restored (false): while cut, every relayed connection is closed
  /// and a new one is accepted and closed at once (the gateway sees its peer drop the link).
  void set_cut(bool cut) { cut_ = cut; }

  std::vector<Frame> frames() {
    std::lock_guard<std::mutex> lock(mutex_);
    return frames_;
  }

 private:
  static sockaddr_in loopback(std::uint16_t port) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(port);
    return a;
  }

  void accept_loop() {
    int connection = 0;
    while (!stop_) {
      const int client = accept(listen_fd_, nullptr, nullptr);
      if (client < 0) return;
      if (cut_) {
        close(client);
        continue;
      }
      const int upstream = socket(AF_INET, SOCK_STREAM, 0);
      sockaddr_in a = loopback(upstream_port_);
      if (connect(upstream, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
        close(upstream);
        close(client);
        continue;
      }
      links_.emplace_back(
          [this, client, upstream, connection] { relay(client, upstream, connection); });
      ++connection;
    }
  }

  // Passes whole frames of `buffer` on to `to`, recording each; keeps a partial frame.
  bool pass_frames(std::vector<std::uint8_t>& buffer, int to, int connection, bool request) {
    while (buffer.size() >= 8) {
      const std::size_t length = 6U + (static_cast<std::size_t>(buffer[4]) << 8U) + buffer[5];
      if (buffer.size() < length) break;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        frames_.push_back({connection, request,
                           static_cast<std::uint16_t>((buffer[0] << 8U) | buffer[1]), buffer[7]});
      }
      if (send(to, buffer.data(), length, MSG_NOSIGNAL) != static_cast<ssize_t>(length)) {
        return false;
      }
      buffer.erase(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(length));
    }
    return true;
  }

  // Relays one connection until either side closes it; then closes both.
  void relay(int client, int upstream, int connection) {
    std::vector<std::uint8_t> from_client, from_upstream;
    std::uint8_t chunk[512];
    while (!stop_ && !cut_) {
      pollfd fds[2] = {{client, POLLIN, 0}, {upstream, POLLIN, 0}};
      if (poll(fds, 2, 100) < 0) break;
      bool open = true;
      for (int s = 0; s < 2 && open; ++s) {
        if ((fds[s].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
        const ssize_t n = recv(fds[s].fd, chunk, sizeof chunk, 0);
        if (n <= 0) {
          open = false;
          break;
        }
        auto& buffer = s == 0 ? from_client : from_upstream;
        buffer.insert(buffer.end(), chunk, chunk + n);
        open = pass_frames(buffer, s == 0 ? upstream : client, connection, s == 0);
      }
      if (!open) break;
    }
    close(client);
    close(upstream);
  }

  std::uint16_t upstream_port_ = 0;
  std::uint16_t port_ = 0;
  int listen_fd_ = -1;
  std::atomic<bool> stop_{false};
  std::atomic<bool> cut_{false};
  std::thread acceptor_;
  std::vector<std::thread> links_;  // touched by the acceptor only, joined after it
  std::mutex mutex_;
  std::vector<Frame> frames_;
};

}  // namespace excite::test
