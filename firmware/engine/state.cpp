// SPDX-License-Identifier: MIT
#include "firmware/engine/state.hpp"

namespace excite::engine {

const char* to_string(State state) noexcept {
  switch (state) {
    case State::configured:
      return "configured";
    case State::armed:
      return "armed";
    case State::running:
      return "running";
    case State::suspended:
      return "suspended";
    case State::completed:
      return "completed";
    case State::aborted:
      return "aborted";
    case State::returning:
      return "returning";
    case State::safe:
      return "safe";
    case State::safe_unconfirmed:
      return "safe, unconfirmed";
  }
  return "unknown";
}

runlog::RunState to_run_state(State state) noexcept {
  switch (state) {
    case State::configured:
      return runlog::RunState::configured;
    case State::armed:
      return runlog::RunState::armed;
    case State::running:
      return runlog::RunState::running;
    case State::suspended:
      return runlog::RunState::suspended;
    case State::completed:
      return runlog::RunState::completed;
    case State::aborted:
      return runlog::RunState::aborted;
    case State::returning:
      return runlog::RunState::returning;
    case State::safe:
      return runlog::RunState::safe;
    case State::safe_unconfirmed:
      return runlog::RunState::safe_unconfirmed;
  }
  return runlog::RunState::unknown;
}

const char* to_string(Command command) noexcept {
  switch (command) {
    case Command::none:
      return "none";
    case Command::start:
      return "start";
    case Command::suspend:
      return "suspend";
    case Command::resume:
      return "resume";
    case Command::abort:
      return "abort";
    case Command::approve:
      return "approve";
  }
  return "unknown";
}

const char* to_string(Outcome outcome) noexcept {
  switch (outcome) {
    case Outcome::none:
      return "none";
    case Outcome::completed:
      return "completed";
    case Outcome::aborted_by_operator:
      return "aborted by operator";
    case Outcome::aborted_on_timeout:
      return "aborted on suspension timeout";
    case Outcome::readback_fault:
      return "fault: readback mismatch";
    case Outcome::log_fault:
      return "fault: the run log could not be written";
    case Outcome::device_refused:
      return "fault: the device refused a request";
    case Outcome::foreign_writer:
      return "fault: another writer was seen";
    case Outcome::aborted_on_controller:
      return "aborted: the controller left its mode or an MV was limited too long";
  }
  return "unknown";
}

Command command_from_code(std::int64_t code) noexcept {
  switch (code) {
    case 1:
      return Command::start;
    case 2:
      return Command::suspend;
    case 3:
      return Command::resume;
    case 4:
      return Command::abort;
    case 5:
      return Command::approve;
    default:
      return Command::none;
  }
}

}  // namespace excite::engine
