// SPDX-License-Identifier: MIT
#include "fault_server.hpp"

#include <arpa/inet.h>
#include <modbus.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace excite::test {

FaultServer::FaultServer(std::uint16_t port) {
  ctx_ = modbus_new_tcp("127.0.0.1", port);
  mapping_ = modbus_mapping_new(0, 0, 65536, 65536);
  if (ctx_ == nullptr || mapping_ == nullptr) {
    std::fprintf(stderr, "FaultServer: %s\n", modbus_strerror(errno));
    std::abort();
  }
  listen_fd_ = modbus_tcp_listen(ctx_, 4);
  if (listen_fd_ == -1) {
    std::fprintf(stderr, "FaultServer: listen on port %u: %s\n", port, modbus_strerror(errno));
    std::abort();
  }
  sockaddr_in address{};
  socklen_t length = sizeof address;
  getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&address), &length);
  port_ = ntohs(address.sin_port);
  thread_ = std::thread([this] { serve(); });
}

FaultServer::~FaultServer() {
  stop();
  modbus_mapping_free(mapping_);
  modbus_free(ctx_);
}

void FaultServer::stop() {
  if (thread_.joinable()) {
    stopping_ = true;
    thread_.join();
  }
  modbus_close(ctx_);
  if (listen_fd_ != -1) {
    close(listen_fd_);
    listen_fd_ = -1;
  }
}

void FaultServer::inject(Fault fault, int requests, std::chrono::milliseconds stall) {
  std::lock_guard lock(mutex_);
  fault_ = fault;
  fault_requests_ = requests;
  stall_ = stall;
}

void FaultServer::set_input(int address, std::uint16_t value) {
  std::lock_guard lock(mutex_);
  mapping_->tab_input_registers[address] = value;
}

void FaultServer::set_holding(int address, std::uint16_t value) {
  std::lock_guard lock(mutex_);
  mapping_->tab_registers[address] = value;
}

std::uint16_t FaultServer::holding(int address) {
  std::lock_guard lock(mutex_);
  return mapping_->tab_registers[address];
}

std::vector<FaultServer::Seen> FaultServer::seen() {
  std::lock_guard lock(mutex_);
  return seen_;
}

int FaultServer::count(int function_code) {
  std::lock_guard lock(mutex_);
  int n = 0;
  for (const Seen& s : seen_) {
    n += s.function_code == function_code ? 1 : 0;
  }
  return n;
}

void FaultServer::clear_seen() {
  std::lock_guard lock(mutex_);
  seen_.clear();
}

void FaultServer::serve() {
  std::uint8_t query[MODBUS_TCP_MAX_ADU_LENGTH];
  const int header = modbus_get_header_length(ctx_);
  while (!stopping_) {
    pollfd fds[2] = {{listen_fd_, POLLIN, 0}, {modbus_get_socket(ctx_), POLLIN, 0}};
    const nfds_t n = fds[1].fd >= 0 ? 2 : 1;
    if (poll(fds, n, 20) <= 0) {
      continue;
    }
    if ((fds[0].revents & POLLIN) != 0) {
      modbus_close(ctx_);  // one client at a time: the newest wins
      int fd = listen_fd_;
      modbus_tcp_accept(ctx_, &fd);
      continue;
    }
    if (n < 2 || fds[1].revents == 0) {
      continue;
    }
    const int length = modbus_receive(ctx_, query);
    if (length <= 0) {  // client closed or sent garbage: forget it
      modbus_close(ctx_);
      continue;
    }
    Fault fault = Fault::none;
    std::chrono::milliseconds stall{0};
    {
      std::lock_guard lock(mutex_);
      seen_.push_back(Seen{query[header], (query[header + 1] << 8) | query[header + 2],
                           (query[header + 3] << 8) | query[header + 4]});
      if (fault_requests_ > 0) {
        fault = fault_;
        stall = stall_;
        --fault_requests_;
      }
    }
    switch (fault) {
      case Fault::drop:
        modbus_close(ctx_);
        continue;
      case Fault::exception:
        modbus_reply_exception(ctx_, query, MODBUS_EXCEPTION_SLAVE_OR_SERVER_FAILURE);
        continue;
      case Fault::refusal:
        modbus_reply_exception(ctx_, query, MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
        continue;
      case Fault::stall:
        std::this_thread::sleep_for(stall);
        break;
      case Fault::none:
        break;
    }
    std::lock_guard lock(mutex_);
    modbus_reply(ctx_, query, length, mapping_);
  }
}

}  // namespace excite::test
