// SPDX-License-Identifier: MIT
#include "hal/can/can_field_bus.hpp"

#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>

namespace excite::hal::can {

namespace {

const char* socket_failure_reason(int error) noexcept {
  switch (error) {
    case EAFNOSUPPORT:
      return "socket(PF_CAN, SOCK_RAW, CAN_RAW) failed: EAFNOSUPPORT (Address family not supported "
             "by "
             "protocol): this kernel has no SocketCAN (AF_CAN)";
    case EPROTONOSUPPORT:
      return "socket(PF_CAN, SOCK_RAW, CAN_RAW) failed: EPROTONOSUPPORT: the can-raw module is not "
             "loaded";
    case EACCES:
    case EPERM:
      return "socket(PF_CAN, SOCK_RAW, CAN_RAW) failed: permission denied";
    default:
      return "socket(PF_CAN, SOCK_RAW, CAN_RAW) failed";
  }
}

}  // namespace

SocketCanSupport probe_socketcan() noexcept {
  const int fd = socket(PF_CAN, SOCK_RAW, CAN_RAW);
  if (fd < 0) {
    return {StatusCode::unavailable, socket_failure_reason(errno)};
  }
  close(fd);
  return {StatusCode::ok, ""};
}

CanFieldBus::~CanFieldBus() {
  release();
}

void CanFieldBus::release() noexcept {
  if (fd_ >= 0) {
    close(fd_);
    fd_ = -1;
  }
}

namespace {

config::Check check_settings(const CanConfig& config) {
  if (config.interface.empty() || config.interface.size() >= IFNAMSIZ) {
    return config::Check::invalid(
        "can.interface", "\"" + config.interface + "\"",
        "an interface name of 1.." + std::to_string(IFNAMSIZ - 1) + " characters");
  }
  if (config.value_timeout_ms < 1 || config.value_timeout_ms > 60000) {
    return config::Check::invalid("can.value_timeout_ms", std::to_string(config.value_timeout_ms),
                                  "1..60000 ms");
  }
  if (config.enobufs_limit < 1) {
    return config::Check::invalid("can.enobufs_limit", "0", "at least 1 write() call");
  }
  if (config.await_echo && *config.await_echo >= config.map.values.size()) {
    return config::Check::invalid(
        "can.await_echo", std::to_string(*config.await_echo),
        "the index of a value (0.." + std::to_string(config.map.values.size()) + " - 1)");
  }
  return config::Check::valid();
}

}  // namespace

config::Check validate(const CanConfig& config) {
  if (config::Check v = check_settings(config); !v.ok()) return v;
  CanPlan plan;
  return compile_frame_map(config.map, plan);
}

config::Check CanFieldBus::prepare(const CanConfig& config, CanPlan& plan) {
  release();
  plan_ = CanPlan{};
  std::snprintf(detail_, sizeof detail_, "not configured");
  if (config::Check v = check_settings(config); !v.ok()) return v;
  return compile_frame_map(config.map, plan);
}

void CanFieldBus::adopt(const CanConfig& config, CanPlan&& plan, int fd) {
  fd_ = fd;
  plan_ = std::move(plan);
  link_ = LinkState(config.enobufs_limit);
  tx_ = plan_.tx;
  latest_.assign(plan_.values.size(), 0.0);
  received_at_.assign(plan_.rx.size(), Nanoseconds{-1});
  value_timeout_ = std::chrono::milliseconds(config.value_timeout_ms);
  await_echo_ = config.await_echo;
  awaited_.reset();
  had_values_ = false;
  interface_ = config.interface;
  clamped_ = 0;
  counters_ = CanCounters{};
  detail_[0] = '\0';
}

config::Check CanFieldBus::configure_on_socket(const CanConfig& config, int fd) {
  CanPlan plan;
  if (auto v = prepare(config, plan); !v.ok()) {
    return v;
  }
  if (fd < 0) {
    return config::Check::invalid("can.socket", std::to_string(fd), "an open socket descriptor");
  }
  adopt(config, std::move(plan), fd);
  return config::Check::valid();
}

config::Check CanFieldBus::configure(const CanConfig& config) {
  CanPlan plan;
  if (auto v = prepare(config, plan); !v.ok()) {
    return v;
  }
  const int fd = socket(PF_CAN, SOCK_RAW, CAN_RAW);
  if (fd < 0) {
    const char* reason = socket_failure_reason(errno);
    std::snprintf(detail_, sizeof detail_, "%s", reason);
    return config::Check::invalid("can.interface", "\"" + config.interface + "\"",
                                  std::string("a usable SocketCAN interface (") + reason + ")");
  }
  auto fail = [&](const char* call) {
    const std::string reason = std::string(call) + " failed: " + std::strerror(errno);
    close(fd);
    std::snprintf(detail_, sizeof detail_, "%s", reason.c_str());
    return config::Check::invalid("can.interface", "\"" + config.interface + "\"",
                                  "an existing, usable CAN interface (" + reason + ")");
  };
  const unsigned int index = if_nametoindex(config.interface.c_str());
  if (index == 0) {
    return fail("if_nametoindex");
  }
  std::vector<can_filter> filters;
  const auto exact = [](canid_t id) {
    return can_filter{id, (id & CAN_EFF_FLAG) != 0 ? (CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_EFF_MASK)
                                                   : (CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_SFF_MASK)};
  };
  for (const RxFrame& rx : plan.rx) filters.push_back(exact(rx.id));
  for (const can_frame& tx : plan.tx) filters.push_back(exact(tx.can_id));
  // No filters means receive nothing but error frames (an empty filter list).
  if (setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, filters.empty() ? nullptr : filters.data(),
                 static_cast<socklen_t>(filters.size() * sizeof(can_filter))) != 0) {
    return fail("setsockopt(CAN_RAW_FILTER)");
  }
  const can_err_mask_t errors = CAN_ERR_MASK;  // every error class, bus-off included
  if (setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &errors, sizeof errors) != 0) {
    return fail("setsockopt(CAN_RAW_ERR_FILTER)");
  }
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(index);
  if (bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    return fail("bind");
  }
  adopt(config, std::move(plan), fd);
  return config::Check::valid();
}

StatusCode CanFieldBus::write(std::span<const double> setpoints, std::uint16_t heartbeat) noexcept {
  if (fd_ < 0) {
    return StatusCode::unavailable;  // detail_ says why (not configured, or no AF_CAN)
  }
  if (pack_setpoints(plan_, setpoints, heartbeat, tx_, clamped_) != StatusCode::ok) {
    std::snprintf(detail_, sizeof detail_,
                  "write: %zu setpoints (%zu configured), all finite expected", setpoints.size(),
                  plan_.setpoints.size());
    return StatusCode::bad_argument;
  }
  int error = 0;
  for (const can_frame& frame : tx_) {
    if (send(fd_, &frame, sizeof frame, MSG_DONTWAIT) != static_cast<ssize_t>(sizeof frame)) {
      error = errno;
      ++counters_.send_failures;
      counters_.last_send_error = error;
      break;
    }
  }
  const StatusCode status = link_.on_write(error);
  if (await_echo_ && status == StatusCode::ok) {
    awaited_ = heartbeat;
  }
  if (status == StatusCode::ok) {
    detail_[0] = '\0';
  } else if (link_.bus_off()) {
    std::snprintf(detail_, sizeof detail_, "%s: controller is bus-off", interface_.c_str());
  } else {
    std::snprintf(detail_, sizeof detail_, "%s: send: %s (%u consecutive)", interface_.c_str(),
                  std::strerror(error), link_.enobufs_streak());
  }
  return status;
}

StatusCode CanFieldBus::read(std::span<double> values) noexcept {
  if (fd_ < 0) {
    return StatusCode::unavailable;
  }
  if (values.size() != plan_.values.size()) {
    std::snprintf(detail_, sizeof detail_, "read: room for %zu values given, %zu configured",
                  values.size(), plan_.values.size());
    return StatusCode::bad_argument;
  }
  if (!drain()) {
    return StatusCode::link_lost;
  }
  if (awaited_) {
    if (const StatusCode s = await_echo(); s != StatusCode::ok) {
      return s;
    }
  }
  if (!had_values_ && !all_received()) {
    (void)wait_until([this] { return all_received(); });  // the check below names what is missing
  }
  if (link_.bus_off()) {
    std::snprintf(detail_, sizeof detail_, "%s: controller is bus-off", interface_.c_str());
    return StatusCode::link_lost;
  }
  const Nanoseconds now = clock_.now();
  for (std::size_t f = 0; f < plan_.rx.size(); ++f) {
    if (received_at_[f].count() < 0 || now - received_at_[f] > value_timeout_) {
      std::snprintf(detail_, sizeof detail_, "%s: value frame 0x%X %s", interface_.c_str(),
                    plan_.rx[f].id & CAN_EFF_MASK,
                    received_at_[f].count() < 0 ? "never received" : "stale");
      ++counters_.stale_reads;
      return StatusCode::timeout;
    }
  }
  std::copy(latest_.begin(), latest_.end(), values.begin());
  detail_[0] = '\0';
  had_values_ = true;
  return StatusCode::ok;
}

bool CanFieldBus::drain() noexcept {
  can_frame frame{};
  while (recv(fd_, &frame, sizeof frame, MSG_DONTWAIT) == static_cast<ssize_t>(sizeof frame)) {
    if ((frame.can_id & CAN_ERR_FLAG) != 0) {
      link_.on_error_frame(frame);
      continue;
    }
    if (const auto rx = find_rx(plan_, frame)) {
      if (unpack_values(plan_, *rx, frame, latest_)) {
        received_at_[*rx] = clock_.now();
      } else if (++counters_.short_frames == 1) {
        counters_.first_short_id = frame.can_id & CAN_EFF_MASK;
        counters_.first_short_dlc = frame.can_dlc;
      }
    } else if (is_own_id(frame) && ++counters_.own_id_frames == 1) {
      counters_.first_own_id = frame.can_id & CAN_EFF_MASK;
    }
  }
  if (errno != EAGAIN && errno != EWOULDBLOCK) {
    std::snprintf(detail_, sizeof detail_, "%s: recv: %s", interface_.c_str(),
                  std::strerror(errno));
    return false;
  }
  return true;
}

bool CanFieldBus::is_own_id(const can_frame& frame) const noexcept {
  const canid_t id = frame.can_id & (CAN_EFF_FLAG | CAN_EFF_MASK);
  return std::any_of(tx_.begin(), tx_.end(), [id](const can_frame& t) { return t.can_id == id; });
}

bool CanFieldBus::all_received() const noexcept {
  return std::none_of(received_at_.begin(), received_at_.end(),
                      [](Nanoseconds t) { return t.count() < 0; });
}

template <class Done>
StatusCode CanFieldBus::wait_until(Done done) noexcept {
  const Nanoseconds deadline = clock_.now() + value_timeout_;
  while (!done()) {
    const Nanoseconds left = deadline - clock_.now();
    const auto ms = std::chrono::ceil<std::chrono::milliseconds>(left).count();
    pollfd p{fd_, POLLIN, 0};
    if (ms <= 0 || poll(&p, 1, static_cast<int>(ms)) <= 0) {
      return StatusCode::timeout;
    }
    if (!drain()) {
      return StatusCode::link_lost;
    }
  }
  return StatusCode::ok;
}

// Frames arrive in the order the peer sent them, so the ones it sent before the echo (its
// answer to that write) are in latest_ once the echo is.
StatusCode CanFieldBus::await_echo() noexcept {
  const auto echoed = [this] { return latest_[*await_echo_] == static_cast<double>(*awaited_); };
  const StatusCode s = wait_until(echoed);
  if (s == StatusCode::timeout) {
    ++counters_.echo_timeouts;
    std::snprintf(detail_, sizeof detail_, "%s: no echo of heartbeat %u within %lld ms",
                  interface_.c_str(), static_cast<unsigned>(*awaited_),
                  static_cast<long long>(value_timeout_.count() / 1000000));
  }
  if (s == StatusCode::ok) {
    awaited_.reset();
  }
  return s;
}

}  // namespace excite::hal::can
