// SPDX-License-Identifier: MIT
#include "sim/server/plant_server.hpp"

#include <arpa/inet.h>
#include <modbus.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "base/config/document.hpp"

namespace excite::sim::server {
namespace {

using Clock = std::chrono::steady_clock;

constexpr auto kPollSlice = std::chrono::milliseconds(50);  // stop request latency bound
constexpr int kMaxCatchUp = 1000;  // plant samples taken at once after a stall at most

std::string system_error(const char* what) {
  return std::string(what) + ": " + std::strerror(errno);
}

}  // namespace

PlantServer::PlantServer(PlantProcess& process, RegisterImage& image, ServeOptions options,
                         ClosedLoop* loop)
    : process_(process),
      image_(image),
      options_(std::move(options)),
      faults_(options_.faults),
      u_(static_cast<std::size_t>(process.inputs())),
      y_(static_cast<std::size_t>(process.outputs())),
      loop_(loop) {
  if (loop_ != nullptr) {
    if (!image_.layout().closed_loop || loop_->inputs() != process.inputs() ||
        loop_->outputs() != process.outputs()) {
      throw std::runtime_error("the controller's registers or sizes do not match the plant");
    }
    mv_offsets_.assign(u_.size(), 0.0);
    sp_offsets_.assign(y_.size(), 0.0);
    y_measured_.assign(y_.size(), 0.0);
    status_.assign(u_.size(), 0);
  }
  if (!options_.lockstep && !(options_.sample_period.count() > 0.0)) {
    throw std::runtime_error("--sample-time-s must be > 0 (wall-clock seconds per sample)");
  }
  // Listen first and open the log last: when either fails, nothing is left behind (no
  // socket, no header-only log).
  try {
    listen();
    open_log();  // on failure it leaves no file behind
  } catch (...) {
    release();
    throw;
  }
  mirror_faults_to_control();
  mirror_counters_to_control();
}

void PlantServer::listen() {
  if (rtu()) {  // a serial line: one master, unit 1
    ctx_ = modbus_new_rtu(options_.rtu_device.c_str(), options_.rtu_baud, 'N', 8, 1);
    if (ctx_ == nullptr) {
      throw std::runtime_error("--modbus-rtu " + options_.rtu_device + ": " +
                               modbus_strerror(errno));
    }
    modbus_set_slave(ctx_, 1);
    if (modbus_connect(ctx_) == -1) {
      throw std::runtime_error("cannot open serial device " + options_.rtu_device + ": " +
                               modbus_strerror(errno));
    }
    return;
  }
  ctx_ = modbus_new_tcp(options_.host.c_str(), options_.port);
  if (ctx_ == nullptr) throw std::runtime_error(system_error("modbus_new_tcp"));
  listen_fd_ = modbus_tcp_listen(ctx_, 4);
  if (listen_fd_ == -1) {
    throw std::runtime_error("cannot listen on " + options_.host + ":" +
                             std::to_string(options_.port) + ": " + modbus_strerror(errno));
  }
  sockaddr_in address{};
  socklen_t length = sizeof address;
  getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&address), &length);
  port_ = ntohs(address.sin_port);
}

// ServeOptions' log settings as the shared run log's (plant_log.hpp).
PlantLogSpec plant_log_spec(const ServeOptions& options, double sample_time_min) {
  return PlantLogSpec{options.log_path,    options.plant_description, sample_time_min,
                      options.time_scales, options.input_names,       options.output_names,
                      options.input_units, options.output_units};
}

void PlantServer::open_log() {
  log_.emplace(plant_log_spec(options_, process_.sample_time_min()));
  if (loop_ != nullptr && !options_.controller_log_path.empty()) {
    controller_log_.emplace(options_.controller_log_path, options_.input_names,
                            options_.output_names, process_.sample_time_min());
  }
}

void PlantServer::release() {
  while (!clients_.empty()) close_client(clients_.size() - 1);
  if (listen_fd_ != -1) close(listen_fd_);
  listen_fd_ = -1;
  if (ctx_ != nullptr && rtu()) modbus_close(ctx_);
  if (ctx_ != nullptr) modbus_free(ctx_);
  ctx_ = nullptr;
  log_.reset();
  controller_log_.reset();
}

PlantServer::~PlantServer() {
  release();
}

void PlantServer::accept_client() {
  const int fd = accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
  if (fd == -1) return;  // the peer gave up before we accepted: nothing to serve
  if (static_cast<int>(clients_.size()) >= options_.max_clients) {
    // Evict the least recently active connection that is not the gateway's.
    std::optional<std::size_t> victim;
    for (std::size_t i = 0; i < clients_.size(); ++i) {
      if (clients_[i].gateway) continue;
      if (!victim || clients_[i].last_activity < clients_[*victim].last_activity) victim = i;
    }
    close_client(victim.value_or(0));
  }
  Client client;
  client.fd = fd;
  client.last_activity = Clock::now();
  clients_.push_back(client);
}

void PlantServer::close_client(std::size_t index) {
  close(clients_[index].fd);
  clients_.erase(clients_.begin() + static_cast<std::ptrdiff_t>(index));
}

void PlantServer::receive(std::size_t index) {
  Client& c = clients_[index];
  // MBAP header: transaction (2), protocol 0 (2), length of unit + PDU (2), unit (1).
  const std::size_t need =
      c.have < 7 ? 7 - c.have : 6 + ((std::size_t{c.frame[4]} << 8) | c.frame[5]) - c.have;
  const ssize_t n = recv(c.fd, c.frame.data() + c.have, need, MSG_DONTWAIT);
  if (n == 0) {  // the peer closed
    close_client(index);
    return;
  }
  if (n < 0) {
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return;
    close_client(index);  // reset
    return;
  }
  const auto now = Clock::now();
  if (c.have == 0) c.request_started = now;
  c.have += static_cast<std::size_t>(n);
  c.last_activity = now;
  if (c.have < 7) return;
  const std::size_t protocol = (std::size_t{c.frame[2]} << 8) | c.frame[3];
  const std::size_t length = (std::size_t{c.frame[4]} << 8) | c.frame[5];
  if (protocol != 0 || length < 2 || length > kMaxAdu - 6) {  // not Modbus TCP: no resync
    ++closed_connections_;
    close_client(index);
    return;
  }
  if (c.have == 6 + length) answer(index, false);
}

PlantServer::Outcome PlantServer::handle(std::uint8_t* query, int length, bool stall_done,
                                         bool& heartbeat_written) {
  heartbeat_written = false;
  const int header = modbus_get_header_length(ctx_);  // 7 (TCP MBAP) or 1 (RTU address)
  const int crc = rtu() ? 2 : 0;
  if (!stall_done) ++requests_;
  const auto replied = [](int rc) { return rc == -1 ? Outcome::close : Outcome::replied; };

  const ParsedRequest parsed = parse_request(query, length, header, crc);
  if (parsed.verdict == RequestVerdict::illegal_function) {
    // not served: answered before any fault, counted, connection kept
    ++illegal_functions_;
    return replied(modbus_reply_exception(ctx_, query, MODBUS_EXCEPTION_ILLEGAL_FUNCTION));
  }
  if (parsed.verdict == RequestVerdict::malformed) {
    return replied(modbus_reply_exception(ctx_, query, MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE));
  }
  ModbusRequest request = parsed.request;
  const bool control = touches_control(request);

  if (!control && !stall_done && faults_armed()) {
    if (faults_.drop_requests > 0) {
      --faults_.drop_requests;
      mirror_faults_to_control();
      ++ordinary_requests_;
      return Outcome::drop;
    }
    if (faults_.exception_requests > 0) {
      --faults_.exception_requests;
      mirror_faults_to_control();
      ++ordinary_requests_;
      return replied(modbus_reply_exception(ctx_, query, MODBUS_EXCEPTION_SLAVE_OR_SERVER_FAILURE));
    }
    if (faults_.stall_requests > 0) {
      --faults_.stall_requests;
      mirror_faults_to_control();
      ++ordinary_requests_;
      return Outcome::stall;
    }
  }
  if (!control && !stall_done) ++ordinary_requests_;

  // Under a controller the MVs are the controller's: a write to a setpoint register is
  // refused as a whole (exception 2), counted and reported; the offsets are written instead.
  if (request.write && loop_ != nullptr &&
      image_.touches_setpoints(request.address, std::max<std::uint32_t>(request.count, 1))) {
    ++refused_writes_;
    mirror_counters_to_control();
    if (refused_writes_ <= 10) {
      std::fprintf(stderr,
                   "excite-plant: write refused (exception 2, illegal data address): register "
                   "%u is a setpoint register, which under --controller carries the applied MV; "
                   "the gateway writes test offsets at registers.offset_address; refused writes: "
                   "%llu\n",
                   request.address, static_cast<unsigned long long>(refused_writes_));
    }
    return replied(modbus_reply_exception(ctx_, query, MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS));
  }
  // The offset limits under a controller, checked before anything is written.
  if (request.write && loop_ != nullptr && !options_.offset_limit.empty()) {
    const bool single = request.function_code == MODBUS_FC_WRITE_SINGLE_REGISTER;
    const std::uint32_t count =
        single ? 1U : std::min<std::uint32_t>(request.count, query[header + 5] / 2U);
    if (refuse_offset_beyond_limit(request.address, count, query + header + (single ? 3 : 6))) {
      return replied(modbus_reply_exception(ctx_, query, MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE));
    }
  }
  // The input limits, checked before anything is written: a refused request writes nothing.
  if (request.write && !options_.input_min.empty()) {
    const bool single = request.function_code == MODBUS_FC_WRITE_SINGLE_REGISTER;
    const std::uint32_t count =
        single ? 1U : std::min<std::uint32_t>(request.count, query[header + 5] / 2U);
    request.count = count;
    if (refuse_out_of_limits(request, query + header + (single ? 3 : 6))) {
      return replied(modbus_reply_exception(ctx_, query, MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE));
    }
  }

  // Tripped: the setpoints written since the trip are put back under this write, so that
  // the image holds them all when the heartbeat moves (below) or they are set aside again.
  if (request.write && watchdog_tripped_ && has_pending_) image_.set_guarded_registers(pending_);
  // The reply writes the registers (or answers an illegal address with an exception).
  const Outcome outcome = replied(modbus_reply(ctx_, query, length, image_.mapping()));
  if (request.write) {
    image_.note_write(request.address, request.count);
    if (control) load_faults_from_control();
    const std::uint32_t hb = image_.layout().heartbeat_address;
    if (request.address <= hb && hb < request.address + request.count) {
      heartbeat_written = true;
      on_heartbeat_written();
    }
    if (watchdog_tripped_) {  // still stale: what was written waits, the safe state holds
      pending_ = image_.guarded_registers();
      has_pending_ = true;
      image_.restore_guarded();
    }
  }
  return outcome;
}

void PlantServer::answer(std::size_t index, bool stall_done) {
  Client& c = clients_[index];
  modbus_set_socket(ctx_, c.fd);
  bool heartbeat = false;
  const Outcome outcome = handle(c.frame.data(), static_cast<int>(c.have), stall_done, heartbeat);
  if (outcome == Outcome::stall) {  // answered later by run(); the others are served meanwhile
    c.reply_at = Clock::now() + std::chrono::milliseconds(faults_.stall_ms);
    return;
  }
  c.reply_at.reset();
  c.have = 0;
  if (heartbeat) {
    for (Client& other : clients_) other.gateway = false;
    c.gateway = true;
  }
  // drop: the fault; close: the peer went away (or stopped reading) while we answered
  if (outcome != Outcome::replied) close_client(index);
}

void PlantServer::serve_rtu(const std::function<bool()>& stop) {
  std::uint8_t query[MODBUS_RTU_MAX_ADU_LENGTH];
  // libmodbus reads the frame (inter-byte timeout) and checks the address and the CRC.
  const int length = modbus_receive(ctx_, query);
  if (length < 0 && (errno == EIO || errno == EBADF || errno == ENXIO)) {
    lose_line(std::strerror(errno));  // not a frame: the line itself is gone
    return;
  }
  if (length <= 0) {  // another unit's request (0), or a bad CRC / garbage: resynchronise
    if (length < 0) {
      ++rejected_frames_;
      modbus_flush(ctx_);
    }
    return;
  }
  bool heartbeat = false;
  if (handle(query, length, false, heartbeat) ==
      Outcome::stall) {  // one master on the line: nobody else waits
    const auto end = Clock::now() + std::chrono::milliseconds(faults_.stall_ms);
    while (!stop() && Clock::now() < end) {
      std::this_thread::sleep_for(std::min<Clock::duration>(kPollSlice, end - Clock::now()));
    }
    handle(query, length, true, heartbeat);
  }
  // drop on a serial line: no reply (the master times out); there is no connection to close
}

void PlantServer::lose_line(const char* why) {
  modbus_close(ctx_);
  line_lost_ = true;
  ++line_losses_;
  std::fprintf(stderr,
               "excite-plant: serial line %s lost (%s): waiting for it to come back (reopened "
               "every 0.5 s)\n",
               options_.rtu_device.c_str(), why);
}

void PlantServer::wait_for_line(const std::function<bool()>& stop) {
  const auto until = Clock::now() + std::chrono::milliseconds(500);
  while (!stop() && Clock::now() < until) std::this_thread::sleep_for(kPollSlice);
  if (stop() || modbus_connect(ctx_) == -1) return;
  line_lost_ = false;
  std::fprintf(stderr, "excite-plant: serial line %s back\n", options_.rtu_device.c_str());
}

void PlantServer::check_deadlines(Clock::time_point now) {
  const auto idle = std::chrono::duration<double>(options_.idle_timeout_s);
  const auto partial = std::chrono::duration<double>(options_.partial_timeout_s);
  for (std::size_t i = clients_.size(); i-- > 0;) {
    Client& c = clients_[i];
    if (c.reply_at) {
      if (now >= *c.reply_at) answer(i, true);
    } else if (c.have > 0 && now - c.request_started > partial) {
      ++closed_connections_;
      close_client(i);
    } else if (c.have == 0 && !c.gateway && now - c.last_activity > idle) {
      ++closed_connections_;
      close_client(i);
    }
  }
}

bool PlantServer::touches_control(const ModbusRequest& request) const {
  if (!image_.layout().control_address || request.function_code == 4) return false;
  const std::uint32_t start = *image_.layout().control_address;
  return request.address < start + control_block_size &&
         start < request.address + std::max<std::uint32_t>(request.count, 1);
}

void PlantServer::load_faults_from_control() {
  if (!image_.layout().control_address) return;
  faults_.stall_ms = image_.control(0);
  faults_.stall_requests = image_.control(1);
  faults_.drop_requests = image_.control(2);
  faults_.exception_requests = image_.control(3);
  faults_.freeze_echo = image_.control(4) != 0;
}

void PlantServer::mirror_faults_to_control() {
  if (!image_.layout().control_address) return;
  image_.set_control(0, faults_.stall_ms);
  image_.set_control(1, faults_.stall_requests);
  image_.set_control(2, faults_.drop_requests);
  image_.set_control(3, faults_.exception_requests);
  image_.set_control(4, faults_.freeze_echo ? 1 : 0);
}

void PlantServer::take_closed_loop_sample() {
  image_.read_offsets(mv_offsets_.data(), sp_offsets_.data());
  const std::uint64_t k = process_.samples();
  loop_->step(y_measured_, image_.controller_switch(), mv_offsets_, sp_offsets_);
  const auto applied = loop_->applied();
  const std::vector<double>& u0 = process_.input_baseline();
  for (std::size_t i = 0; i < u_.size(); ++i) u_[i] = u0[i] + applied[i];
  process_.sample(u_.data(), y_.data());
  image_.write_values(y_.data());
  report_misfits(k);
  const std::vector<double>& dy = process_.last_dy();
  std::copy(dy.begin(), dy.end(), y_measured_.begin());
  for (std::size_t i = 0; i < status_.size(); ++i) {
    status_[i] = static_cast<std::uint16_t>(loop_->status()[i]);
  }
  image_.write_controller(loop_->moves().data(), applied.data(), loop_->setpoints().data(),
                          status_.data(), static_cast<std::uint16_t>(loop_->mode()), u_.data());
  if (log_) log_->write(k, process_.last_du(), u_, dy);
  if (controller_log_) controller_log_->write("sample", k, *loop_);
}

void PlantServer::take_sample() {
  if (loop_ != nullptr) {
    take_closed_loop_sample();
    return;
  }
  image_.read_setpoints(u_.data());
  const std::uint64_t k = process_.samples();
  process_.sample(u_.data(), y_.data());
  image_.write_values(y_.data());
  report_misfits(k);
  if (log_) log_->write(k, process_.last_du(), u_, process_.last_dy());
}

void PlantServer::report_misfits(std::uint64_t k) {
  const auto& misfits = image_.misfits();
  misfits_reported_.resize(misfits.size(), 0);
  std::uint64_t total = 0;
  for (std::size_t j = 0; j < misfits.size(); ++j) {
    total += misfits[j].count;
    if (misfits[j].count == 0 || misfits_reported_[j] != 0) continue;
    misfits_reported_[j] = misfits[j].count;  // the first misfit of each output, at once
    const hal::modbus::Codec& codec = image_.layout().values[j].codec;
    std::fprintf(stderr,
                 "excite-plant: sample %llu: output %s = %.9g does not fit its register (%s "
                 "range [%g, %g]): the register holds the range's end; counted, summary at "
                 "stop\n",
                 static_cast<unsigned long long>(k),
                 j < options_.output_names.size() ? options_.output_names[j].c_str() : "?", y_[j],
                 codec.type == hal::modbus::RegisterType::int16 ? "int16" : "uint16", codec.eng_min,
                 codec.eng_max);
  }
  if (image_.layout().control_address) {
    image_.set_control(5, static_cast<std::uint16_t>(std::min<std::uint64_t>(total, 65535)));
  }
}

bool PlantServer::refuse_out_of_limits(const ModbusRequest& request, const std::uint8_t* data) {
  const auto out = image_.check_write(request.address, request.count, data, options_.input_min,
                                      options_.input_max);
  if (!out) return false;
  ++refused_writes_;
  mirror_counters_to_control();
  if (refused_writes_ <= 10) {  // the first ten at once; the count at stop
    const std::size_t i = out->input;
    std::fprintf(stderr,
                 "excite-plant: write refused (exception 3, illegal data value): input %s = "
                 "%.9g outside its limits [%.9g, %.9g]; refused writes: %llu\n",
                 i < options_.input_names.size() ? options_.input_names[i].c_str() : "?",
                 out->value, options_.input_min[i], options_.input_max[i],
                 static_cast<unsigned long long>(refused_writes_));
  }
  return true;
}

bool PlantServer::refuse_offset_beyond_limit(std::uint32_t address, std::uint32_t count,
                                             const std::uint8_t* data) {
  const auto out = image_.check_offset_write(address, count, data, options_.offset_limit);
  if (!out) return false;
  ++refused_writes_;
  mirror_counters_to_control();
  if (refused_writes_ <= 10) {  // the first ten at once; the count at stop
    const std::size_t k = out->input;
    const std::size_t n = options_.input_names.size();
    const std::string name = k < n ? "MV " + options_.input_names[k] + "'s test offset"
                             : k - n < options_.output_names.size()
                                 ? "CV " + options_.output_names[k - n] + "'s setpoint offset"
                                 : std::string("offset ?");
    std::fprintf(stderr,
                 "excite-plant: write refused (exception 3, illegal data value): %s = %.9g "
                 "beyond its limit ±%.9g (plant.offset_limit[%zu]); refused writes: %llu\n",
                 name.c_str(), out->value, options_.offset_limit[k], k,
                 static_cast<unsigned long long>(refused_writes_));
  }
  return true;
}

void PlantServer::check_watchdog(Clock::time_point now) {
  if (!(options_.watchdog_s > 0.0) || !heartbeat_seen_ || watchdog_tripped_) return;
  const double stale_s = std::chrono::duration<double>(now - heartbeat_changed_at_).count();
  if (stale_s < options_.watchdog_s) return;
  watchdog_tripped_ = true;
  has_pending_ = false;
  image_.restore_guarded();
  ++watchdog_trips_;
  mirror_counters_to_control();
  if (loop_ != nullptr) {  // every offset to zero, the controller kept in control
    loop_->clear_offsets();
    const std::vector<double>& u0 = process_.input_baseline();
    for (std::size_t i = 0; i < u_.size(); ++i) u_[i] = u0[i] + loop_->applied()[i];
    for (std::size_t i = 0; i < status_.size(); ++i) {
      status_[i] = static_cast<std::uint16_t>(loop_->status()[i]);
    }
    image_.write_controller(loop_->moves().data(), loop_->applied().data(),
                            loop_->setpoints().data(), status_.data(),
                            static_cast<std::uint16_t>(loop_->mode()), u_.data());
    if (controller_log_) controller_log_->write("watchdog", process_.samples(), *loop_);
    std::fprintf(
        stderr,
        "excite-plant: watchdog: heartbeat unchanged for %.3f s (limit %g s): every "
        "test offset returned to zero, the controller stays in %.*s (trip %llu); held "
        "there until the heartbeat moves\n",
        stale_s, options_.watchdog_s, static_cast<int>(runlog::to_text(loop_->mode()).size()),
        runlog::to_text(loop_->mode()).data(), static_cast<unsigned long long>(watchdog_trips_));
    return;
  }
  std::fprintf(stderr,
               "excite-plant: watchdog: heartbeat unchanged for %.3f s (limit %g s): inputs "
               "returned to the baseline (trip %llu); held there until the heartbeat moves\n",
               stale_s, options_.watchdog_s, static_cast<unsigned long long>(watchdog_trips_));
}

void PlantServer::mirror_counters_to_control() {
  if (!image_.layout().control_address) return;
  const auto saturated = [](std::uint64_t n) {
    return static_cast<std::uint16_t>(std::min<std::uint64_t>(n, 65535));
  };
  image_.set_control(6, saturated(watchdog_trips_));
  image_.set_control(7, saturated(refused_writes_));
}

void PlantServer::on_heartbeat_written() {
  const std::uint16_t heartbeat = image_.heartbeat();
  if (heartbeat_seen_ && heartbeat == last_heartbeat_) return;
  heartbeat_seen_ = true;
  last_heartbeat_ = heartbeat;
  heartbeat_changed_at_ = Clock::now();
  if (watchdog_tripped_) {      // the gateway is back: what it wrote meanwhile applies
    watchdog_tripped_ = false;  // the image already holds what was written (handle())
    has_pending_ = false;
    std::fprintf(stderr, "excite-plant: watchdog: heartbeat moves again: setpoints apply\n");
  }
  if (options_.lockstep) take_sample();
  if (!(faults_armed() && faults_.freeze_echo)) image_.set_heartbeat_echo(heartbeat);
}

void PlantServer::freeze(const std::function<bool()>& stop) {
  frozen_ = true;
  std::fprintf(stderr,
               "excite-plant: frozen for %u ms after %llu requests at sample %llu (nothing read, "
               "answered or sampled)\n",
               options_.freeze_ms, static_cast<unsigned long long>(requests_),
               static_cast<unsigned long long>(process_.samples()));
  std::fflush(stderr);
  const auto until = Clock::now() + std::chrono::milliseconds(options_.freeze_ms);
  while (Clock::now() < until && !stop()) {
    std::this_thread::sleep_for(std::min<Clock::duration>(until - Clock::now(), kPollSlice));
  }
  std::fprintf(stderr, "excite-plant: running again after the freeze\n");
  std::fflush(stderr);
}

void PlantServer::run(const std::function<bool()>& stop) {
  for (Client& c : clients_) c.last_activity = Clock::now();
  const auto period = std::chrono::duration_cast<Clock::duration>(
      options_.lockstep ? std::chrono::duration<double>(1.0) : options_.sample_period);
  auto next_sample = Clock::now();
  std::vector<pollfd> fds;
  while (!stop()) {
    if (options_.freeze_ms > 0 && !frozen_ && requests_ >= options_.freeze_after) freeze(stop);
    check_watchdog(Clock::now());
    if (!options_.lockstep) {  // free-running: every sample whose time has come
      int taken = 0;
      auto now = Clock::now();
      while (now >= next_sample && taken < kMaxCatchUp) {
        take_sample();
        next_sample += period;
        ++taken;
      }
      if (now >= next_sample) next_sample = now + period;  // too far behind: skip ahead
    }
    auto wait = std::chrono::duration_cast<std::chrono::nanoseconds>(kPollSlice);
    if (!options_.lockstep) {
      wait = std::clamp(
          std::chrono::duration_cast<std::chrono::nanoseconds>(next_sample - Clock::now()),
          std::chrono::nanoseconds(0), wait);
    }
    for (const Client& c : clients_) {
      if (c.reply_at)
        wait = std::clamp(
            std::chrono::duration_cast<std::chrono::nanoseconds>(*c.reply_at - Clock::now()),
            std::chrono::nanoseconds(0), wait);
    }
    fds.clear();
    if (rtu()) {
      if (line_lost_) {  // paced: no spinning on a line that is gone
        wait_for_line(stop);
        continue;
      }
      fds.push_back({modbus_get_socket(ctx_), POLLIN, 0});
      const timespec timeout{static_cast<time_t>(wait.count() / 1000000000),
                             static_cast<long>(wait.count() % 1000000000)};
      const int ready = ppoll(fds.data(), fds.size(), &timeout, nullptr);
      if (ready < 0 && errno != EINTR) throw std::runtime_error(system_error("ppoll"));
      if (ready > 0 && (fds[0].revents & (POLLHUP | POLLERR | POLLNVAL)) != 0) {
        lose_line((fds[0].revents & POLLHUP) != 0 ? "hang-up" : "error");
        continue;
      }
      if (ready > 0) serve_rtu(stop);
      continue;
    }
    fds.push_back({listen_fd_, POLLIN, 0});
    // A stalled connection is not read until its reply is sent (fd −1: poll skips it).
    for (const Client& c : clients_) fds.push_back({c.reply_at ? -1 : c.fd, POLLIN, 0});
    const timespec timeout{static_cast<time_t>(wait.count() / 1000000000),
                           static_cast<long>(wait.count() % 1000000000)};
    const int ready = ppoll(fds.data(), fds.size(), &timeout, nullptr);
    if (ready < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(system_error("ppoll"));
    }
    // Serve clients from the newest down, so closing one does not shift the others' slots.
    for (std::size_t i = fds.size() - 1; ready > 0 && i >= 1; --i) {
      if (fds[i].revents != 0 && i - 1 < clients_.size() && clients_[i - 1].fd == fds[i].fd) {
        receive(i - 1);
      }
    }
    check_deadlines(Clock::now());
    if ((fds[0].revents & POLLIN) != 0) accept_client();
  }
  while (!clients_.empty()) close_client(clients_.size() - 1);
}

namespace {

void print_summary(const PlantProcess& process, const PlantServer& server,
                   const RegisterImage& image, const ServerLayout& layout,
                   const ServeOptions& options) {
  std::cerr << "excite-plant: stopped after " << process.samples() << " samples, "
            << server.requests() << " requests, " << server.rejected_frames()
            << " rejected frames, " << server.line_losses() << " serial line losses, "
            << server.illegal_functions() << " illegal functions, " << server.closed_connections()
            << " connections closed by the server, " << image.clamped_values()
            << " values did not fit their registers, " << server.watchdog_trips()
            << " watchdog trips, " << server.refused_writes()
            << " writes refused for the input limits\n";
  for (std::size_t j = 0; j < image.misfits().size(); ++j) {
    const RegisterImage::Misfit& m = image.misfits()[j];
    if (m.count == 0) continue;
    const PlacedValue& p = layout.values[j];
    std::cerr << "excite-plant: output " << options.output_names[j] << ": " << m.count
              << " samples outside its register's range [" << p.codec.eng_min << ", "
              << p.codec.eng_max << "] (lowest " << m.lowest << ", highest " << m.highest
              << "); the register held the range's end\n";
  }
}

}  // namespace

int serve_modbus(PlantProcess& process, RegisterImage& image, const ServerLayout& layout,
                 const ServeOptions& options, bool default_map, const std::function<void()>& ready,
                 const std::function<bool()>& stop, ClosedLoop* loop) {
  std::unique_ptr<PlantServer> server;
  try {
    server = std::make_unique<PlantServer>(process, image, options, loop);
  } catch (const std::exception& e) {
    std::cerr << "excite-plant: " << e.what() << "\n";
    return 1;
  }
  ready();
  if (options.rtu_device.empty()) {
    std::printf("listening %s:%u\n", options.host.c_str(), static_cast<unsigned>(server->port()));
  } else {  // the same shape: DEVICE:BAUD
    std::printf("listening %s:%d\n", options.rtu_device.c_str(), options.rtu_baud);
  }
  std::fflush(stdout);
  const Plant& plant = process.plant();
  std::cerr << "excite-plant: " << options.plant_description << ", " << plant.inputs()
            << " inputs, " << plant.outputs() << " outputs, T = " << process.sample_time_min()
            << " min, "
            << (options.lockstep ? std::string("lock-step")
                                 : std::to_string(options.sample_period.count()) + " s per sample")
            << (default_map ? ", default register map" : "")
            << (options.watchdog_s > 0.0
                    ? ", watchdog " + config::format_number(options.watchdog_s) + " s"
                    : std::string(", no watchdog"))
            << (options.input_min.empty() ? ", no input limits" : ", input limits")
            << (loop != nullptr ? ", controller in the loop" : "") << "\n";
  int code = 0;
  try {
    server->run(stop);
  } catch (const std::exception& e) {
    std::cerr << "excite-plant: " << e.what() << "\n";
    code = 1;
  }
  print_summary(process, *server, image, layout, options);
  if (loop != nullptr) {
    std::cerr << "excite-plant: controller: mode " << runlog::to_text(loop->mode()) << " at stop, "
              << loop->irregular_steps() << " steps held or at the QP's iteration cap\n";
  }
  if (!server->controller_log_failure().empty() && code == 0) code = 3;
  if (!server->log_failure().empty()) {
    std::cerr << "excite-plant: " << server->log_failure() << "\n";
    if (code == 0) code = 3;
  }
  return code;
}

}  // namespace excite::sim::server
