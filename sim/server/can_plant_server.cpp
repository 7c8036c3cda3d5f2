// SPDX-License-Identifier: MIT
#include "sim/server/can_plant_server.hpp"

#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "sim/server/can_map.hpp"

namespace excite::sim::server {

namespace {

std::string errno_text(const std::string& what) {
  return what + ": " + std::strerror(errno);
}

// Where a float32 setpoint may round to beyond its limit (the Modbus side's slack).
bool inside(double value, double low, double high) {
  const double slack = std::ldexp(std::max(std::fabs(low), std::fabs(high)), -23);
  return std::isfinite(value) && value >= low - slack && value <= high + slack;
}

}  // namespace

CanPlantServer::CanPlantServer(PlantProcess& process, const hal::can::CanFrameMap& plant_map,
                               ServeOptions options, std::string interface, int resend_ms)
    : process_(process),
      options_(std::move(options)),
      interface_(std::move(interface)),
      resend_(std::chrono::milliseconds(resend_ms)) {
  if (!options_.lockstep && !(options_.sample_period.count() > 0.0)) {
    throw std::runtime_error("--sample-time-s must be > 0 (wall-clock seconds per sample)");
  }
  if (const config::Check v = hal::can::compile_frame_map(plant_map, plan_); !v.ok()) {
    throw std::runtime_error("--can " + interface_ + ": frame map: " + v.message());
  }
  const auto n = static_cast<std::size_t>(process_.inputs());
  const auto m = static_cast<std::size_t>(process_.outputs());
  if (plan_.values.size() != n + 1 || plan_.setpoints.size() != m + n || !plan_.heartbeat) {
    throw std::runtime_error("--can " + interface_ + ": frame map does not fit the plant");
  }
  received_.assign(n + 1, 0.0);
  written_ = process_.input_baseline();
  applied_ = written_;
  y_ = process_.output_baseline();
  answer_.assign(m + n, 0.0);
  tx_ = plan_.tx;

  fd_ = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (fd_ < 0) {
    throw std::runtime_error("--can = \"" + interface_ +
                             "\", expected a usable SocketCAN interface (" +
                             errno_text("socket(PF_CAN, SOCK_RAW, CAN_RAW)") + ")");
  }
  const unsigned int index = if_nametoindex(interface_.c_str());
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(index);
  if (index == 0 || bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    const std::string reason = "--can = \"" + interface_ +
                               "\", expected an existing CAN interface (" +
                               errno_text(index == 0 ? "if_nametoindex" : "bind") + ")";
    close(fd_);
    throw std::runtime_error(reason);
  }
  try {
    open_log();
  } catch (...) {
    close(fd_);
    throw;
  }
}

CanPlantServer::~CanPlantServer() {
  if (fd_ >= 0) close(fd_);
}

void CanPlantServer::open_log() {
  log_.emplace(plant_log_spec(options_, process_.sample_time_min()));
}

void CanPlantServer::receive(const can_frame& frame) {
  ++frames_received_;
  const auto rx = hal::can::find_rx(plan_, frame);
  if (!rx) {
    ++foreign_frames_;
    return;
  }
  std::vector<double> decoded = received_;
  if (!hal::can::unpack_values(plan_, *rx, frame, decoded)) {
    if (++wrong_dlc_ <= 10) {
      std::fprintf(stderr,
                   "excite-plant: frame 0x%X refused: DLC %u, expected at least %u; refused "
                   "frames (DLC): %llu\n",
                   frame.can_id & CAN_EFF_MASK, static_cast<unsigned>(frame.can_dlc),
                   static_cast<unsigned>(plan_.rx[*rx].dlc),
                   static_cast<unsigned long long>(wrong_dlc_));
    }
    return;
  }
  // The setpoints this frame carries, checked against the limits before any applies.
  const std::size_t n = written_.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (plan_.values[i].frame != *rx || options_.input_min.empty()) continue;
    if (!inside(decoded[i], options_.input_min[i], options_.input_max[i])) {
      if (++refused_frames_ <= 10) {
        std::fprintf(stderr,
                     "excite-plant: frame 0x%X refused: input %s = %.9g outside its limits "
                     "[%.9g, %.9g]; refused frames (limits): %llu\n",
                     frame.can_id & CAN_EFF_MASK,
                     i < options_.input_names.size() ? options_.input_names[i].c_str() : "?",
                     decoded[i], options_.input_min[i], options_.input_max[i],
                     static_cast<unsigned long long>(refused_frames_));
      }
      return;
    }
  }
  received_ = decoded;
  for (std::size_t i = 0; i < n; ++i) {
    if (plan_.values[i].frame == *rx) written_[i] = received_[i];
  }
  if (!tripped_) applied_ = written_;
  if (plan_.values[n].frame == *rx) on_heartbeat(static_cast<std::uint16_t>(received_[n]));
}

void CanPlantServer::on_heartbeat(std::uint16_t heartbeat) {
  if (heartbeat_seen_ && heartbeat == last_heartbeat_) return;
  heartbeat_seen_ = true;
  last_heartbeat_ = heartbeat;
  heartbeat_changed_at_ = Clock::now();
  if (tripped_) {  // the gateway is back: what it wrote meanwhile applies
    tripped_ = false;
    applied_ = written_;
    std::fprintf(stderr, "excite-plant: watchdog: heartbeat moves again: setpoints apply\n");
  }
  if (!options_.faults.freeze_echo) echo_ = heartbeat;
  if (options_.lockstep) take_sample();
  send_answer();
}

void CanPlantServer::check_watchdog(Clock::time_point now) {
  if (!(options_.watchdog_s > 0.0) || !heartbeat_seen_ || tripped_) return;
  const double stale_s = std::chrono::duration<double>(now - heartbeat_changed_at_).count();
  if (stale_s < options_.watchdog_s) return;
  tripped_ = true;
  ++watchdog_trips_;
  applied_ = process_.input_baseline();
  std::fprintf(stderr,
               "excite-plant: watchdog: heartbeat unchanged for %.3f s (limit %g s): inputs "
               "returned to the baseline (trip %llu); held there until the heartbeat moves\n",
               stale_s, options_.watchdog_s, static_cast<unsigned long long>(watchdog_trips_));
  send_answer();  // the readbacks show the baseline at once
}

void CanPlantServer::take_sample() {
  const std::uint64_t k = process_.samples();
  process_.sample(applied_.data(), y_.data());
  if (log_) log_->write(k, process_.last_du(), applied_, process_.last_dy());
}

// Outputs, readbacks, then the echo (its own frame, last): a gateway that has the echo of
// its heartbeat has this answer's values.
void CanPlantServer::send_answer() {
  std::copy(y_.begin(), y_.end(), answer_.begin());
  std::copy(applied_.begin(), applied_.end(), answer_.begin() + static_cast<long>(y_.size()));
  if (hal::can::pack_setpoints(plan_, answer_, echo_, tx_, clamped_) != hal::StatusCode::ok) {
    return;  // a non-finite output: nothing sent, the gateway sees the values go stale
  }
  for (const can_frame& frame : tx_) {
    // A full transmit queue (ENOBUFS, a flooded bus) loses this answer; the next one or
    // the cyclic repeat carries the values again.
    if (send(fd_, &frame, sizeof frame, MSG_DONTWAIT) == static_cast<ssize_t>(sizeof frame)) {
      ++frames_sent_;
    }
  }
  last_sent_ = Clock::now();
}

void CanPlantServer::run(const std::function<bool()>& stop) {
  const auto period = std::chrono::duration_cast<Clock::duration>(
      options_.lockstep ? std::chrono::duration<double>(1.0) : options_.sample_period);
  auto next_sample = Clock::now();
  send_answer();
  while (!stop()) {
    auto now = Clock::now();
    check_watchdog(now);
    if (!options_.lockstep && now >= next_sample) {
      take_sample();
      send_answer();
      next_sample += period;
      if (now >= next_sample) next_sample = now + period;  // too far behind: skip ahead
    }
    if (now - last_sent_ >= resend_) send_answer();
    auto wake = std::min(last_sent_ + resend_, now + std::chrono::milliseconds(50));
    if (!options_.lockstep) wake = std::min(wake, next_sample);
    const auto wait_ms = std::chrono::ceil<std::chrono::milliseconds>(wake - Clock::now()).count();
    pollfd p{fd_, POLLIN, 0};
    const int ready = poll(&p, 1, static_cast<int>(std::max<long long>(wait_ms, 0)));
    if (ready < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(errno_text("--can " + interface_ + ": poll"));
    }
    can_frame frame{};
    while (recv(fd_, &frame, sizeof frame, MSG_DONTWAIT) == static_cast<ssize_t>(sizeof frame)) {
      if ((frame.can_id & CAN_ERR_FLAG) == 0) receive(frame);
    }
    if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
      throw std::runtime_error(errno_text("--can " + interface_ + ": recv"));
    }
  }
}

int serve_can(PlantProcess& process, const ServeOptions& options, const std::string& interface,
              const std::function<void()>& ready, const std::function<bool()>& stop) {
  const Plant& plant = process.plant();
  std::unique_ptr<CanPlantServer> server;
  try {
    const CanLoopMap map =
        default_can_map(plant.inputs(), plant.outputs(), plant.input_names(), plant.output_names());
    server = std::make_unique<CanPlantServer>(process, map.plant, options, interface);
  } catch (const std::exception& e) {
    std::cerr << "excite-plant: " << e.what() << "\n";
    return 1;
  }
  ready();
  std::printf("listening can %s\n", interface.c_str());
  std::fflush(stdout);
  std::cerr << "excite-plant: " << options.plant_description << ", " << plant.inputs()
            << " inputs, " << plant.outputs() << " outputs, T = " << process.sample_time_min()
            << " min, "
            << (options.lockstep ? std::string("lock-step")
                                 : std::to_string(options.sample_period.count()) + " s per sample")
            << ", default CAN frame map on " << interface
            << (options.watchdog_s > 0.0 ? ", watchdog " + std::to_string(options.watchdog_s) + " s"
                                         : std::string(", no watchdog"))
            << (options.input_min.empty() ? ", no input limits" : ", input limits") << "\n";
  int code = 0;
  try {
    server->run(stop);
  } catch (const std::exception& e) {
    std::cerr << "excite-plant: " << e.what() << "\n";
    code = 1;
  }
  std::cerr << "excite-plant: stopped after " << process.samples() << " samples, "
            << server->frames_received() << " frames received, " << server->frames_sent()
            << " frames sent, " << server->wrong_dlc() << " frames refused for their DLC, "
            << server->refused_frames() << " frames refused for the input limits, "
            << server->foreign_frames() << " frames of other identifiers, "
            << server->watchdog_trips() << " watchdog trips\n";
  if (!server->log_failure().empty()) {
    std::cerr << "excite-plant: " << server->log_failure() << "\n";
    if (code == 0) code = 3;
  }
  return code;
}

}  // namespace excite::sim::server
