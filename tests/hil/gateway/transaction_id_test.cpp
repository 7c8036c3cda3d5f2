// SPDX-License-Identifier: MIT
// Reconnect hygiene, the transaction identifier (issue 10 item 2): a Modbus TCP peer whose
// replies carry another transaction identifier than the request's — a stale reply, from the
// gateway's side — is never taken for the answer. libmodbus checks the identifier
// (_modbus_tcp_pre_check_confirmation → EMBBADDATA); the hal treats it as a malformed reply
// (flush, peer_error); the real excite-gateway refuses to arm (exit 5) naming it, and writes
// nothing. A raw-socket peer, so the wrong identifier is really on the wire.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "gateway_process.hpp"

namespace excite::test {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

// Answers every read (FC03/FC04) with zeros of the requested count under transaction id + 1,
// every other request likewise shifted; counts the function codes it was sent.
class WrongTidPeer {
 public:
  WrongTidPeer() {
    listen_fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bind(listen_fd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t len = sizeof a;
    getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    listen(listen_fd_, 8);
    thread_ = std::thread([this] { serve(); });
  }
  ~WrongTidPeer() {
    stop_ = true;
    thread_.join();
    close(listen_fd_);
  }
  std::uint16_t port() const { return port_; }
  int requests(int function_code) const { return counts_[function_code & 0xFF].load(); }

 private:
  void serve() {
    std::vector<int> clients;
    while (!stop_) {
      std::vector<pollfd> fds{{listen_fd_, POLLIN, 0}};
      for (int c : clients) fds.push_back({c, POLLIN, 0});
      if (poll(fds.data(), fds.size(), 20) <= 0) continue;
      if ((fds[0].revents & POLLIN) != 0) clients.push_back(accept(listen_fd_, nullptr, nullptr));
      for (std::size_t i = 1; i < fds.size(); ++i) {
        if ((fds[i].revents & (POLLIN | POLLHUP)) != 0 && !answer(fds[i].fd)) {
          close(fds[i].fd);
          std::erase(clients, fds[i].fd);
        }
      }
    }
    for (int c : clients) close(c);
  }

  bool answer(int fd) {
    std::uint8_t req[260];
    if (recv(fd, req, 7, MSG_WAITALL) != 7) return false;
    const int length = (req[4] << 8) | req[5];  // unit id + PDU
    if (length < 2 || length > 253 ||
        recv(fd, req + 7, static_cast<std::size_t>(length - 1), MSG_WAITALL) != length - 1) {
      return false;
    }
    const int fc = req[7];
    ++counts_[fc];
    const auto tid = static_cast<std::uint16_t>(((req[0] << 8) | req[1]) + 1);  // not theirs
    std::vector<std::uint8_t> rsp = {static_cast<std::uint8_t>(tid >> 8),
                                     static_cast<std::uint8_t>(tid & 0xFF),
                                     0,
                                     0,
                                     0,
                                     0,
                                     req[6],
                                     static_cast<std::uint8_t>(fc)};
    if (fc == 3 || fc == 4) {
      const int count = (req[10] << 8) | req[11];
      rsp.push_back(static_cast<std::uint8_t>(2 * count));
      rsp.insert(rsp.end(), static_cast<std::size_t>(2 * count), 0);
    } else {
      rsp.insert(rsp.end(), req + 8, req + 12);  // FC16 echo: address and count
    }
    const std::size_t pdu = rsp.size() - 6;
    rsp[4] = static_cast<std::uint8_t>(pdu >> 8);
    rsp[5] = static_cast<std::uint8_t>(pdu & 0xFF);
    return send(fd, rsp.data(), rsp.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(rsp.size());
  }

  int listen_fd_ = -1;
  std::uint16_t port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<int> counts_[256] = {};
  std::thread thread_;
};

TEST(GatewayTransactionId, RepliesWithAnotherTransactionIdAreNeverTaken) {
  const fs::path dir = fs::temp_directory_path() / ("excite_gw_tid_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string plan = (dir / "p.plan").string();
  const std::string design =
      std::string(EXCITE_TOOL) + " design -q --plant woodberry2x2 --preset prbsUnc -o " + plan;
  ASSERT_EQ(std::system(design.c_str()), 0) << design;
  WrongTidPeer peer;
  // Limits around 0, so zeros taken for the answer would arm: only the identifier refuses.
  std::ofstream(dir / "gw.toml") << "[gateway]\nrealtime_priority = 0\nperiod_s = 0.01\n"
                                    "[device]\ntransport = \"modbus-tcp\"\nhost = \"127.0.0.1\"\n"
                                    "port = "
                                 << peer.port() << R"(
unit_id = 1
response_timeout_ms = 200
[map]
heartbeat_address = 104
[[setpoints]]
name = "u1"
address = 100
type = "float32"
min = -5.0
max = 5.0
max_move = 10.0
readback = "u1_sp"
[[setpoints]]
name = "u2"
address = 102
type = "float32"
min = -5.0
max = 5.0
max_move = 10.0
readback = "u2_sp"
[[values]]
name = "y1"
address = 200
function_code = 4
type = "float32"
[[values]]
name = "y2"
address = 202
function_code = 4
type = "float32"
[[values]]
name = "u1_sp"
role = "readback"
address = 100
function_code = 3
type = "float32"
[[values]]
name = "u2_sp"
role = "readback"
address = 102
function_code = 3
type = "float32"
)";
  GatewayProcess gw(EXCITE_GATEWAY,
                    {"--config", (dir / "gw.toml").string(), "--plan", plan, "--log",
                     (dir / "run.csv").string(), "--start", "--allow-distortion"},
                    (dir / "gw").string());
  const auto rc = gw.wait(30s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 5) << gw.err();
  EXPECT_NE(gw.err().find("first read of the live values = peer_error"), std::string::npos)
      << gw.err();
  EXPECT_NE(gw.err().find("Invalid data"), std::string::npos) << gw.err();
  EXPECT_GT(peer.requests(4) + peer.requests(3), 0) << "the peer was asked";
  EXPECT_EQ(peer.requests(16), 0) << "nothing may be written after a reply that is not ours";
  EXPECT_FALSE(fs::exists(dir / "run.csv"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace excite::test
