// SPDX-License-Identifier: MIT
#pragma once
// The gate of every test that needs a SocketCAN bus: where the kernel has no AF_CAN or the
// interface is missing, the test skips naming why; inside the CAN test VM
// (toolchain/can-vm sets EXCITE_CAN_VM) the same reason fails it, since there the bus
// must be there and a skip would hide that the CAN path never ran.
#include <gtest/gtest.h>
#include <net/if.h>

#include <cstdlib>
#include <string>

#include "hal/can/can_field_bus.hpp"

namespace excite::test {

// Empty when SocketCAN works here and `iface` exists (nullptr: AF_CAN alone); else why not.
inline std::string why_no_socketcan(const char* iface) {
  const hal::can::SocketCanSupport support = hal::can::probe_socketcan();
  if (support.status != hal::StatusCode::ok) {
    return std::string("no SocketCAN in this kernel (") + support.reason +
           "): toolchain/can-vm runs this test in a VM with vcan0 and vcan1";
  }
  if (iface != nullptr && if_nametoindex(iface) == 0) {
    return std::string("SocketCAN is there but no ") + iface + ": ip link add " + iface +
           " type vcan; ip link set " + iface + " up";
  }
  return {};
}

inline bool inside_can_vm() {
  return std::getenv("EXCITE_CAN_VM") != nullptr;
}

}  // namespace excite::test

// Skips (outside the VM) or fails (inside) the current test when `iface` is not usable.
#define EXCITE_REQUIRE_SOCKETCAN(iface)                                       \
  if (const std::string excite_why = ::excite::test::why_no_socketcan(iface); \
      !excite_why.empty()) {                                                  \
    if (::excite::test::inside_can_vm()) {                                    \
      FAIL() << "inside the CAN VM: " << excite_why;                          \
    }                                                                         \
    GTEST_SKIP() << excite_why;                                               \
  }
