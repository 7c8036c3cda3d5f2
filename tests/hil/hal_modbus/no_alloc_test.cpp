// SPDX-License-Identifier: MIT
// Proves the exchange path does not allocate (STYLE.md practice 5): global operator
// new/delete are replaced in this binary and count calls made by the test's thread while
// counting is on; 1000 exchanges against a real libmodbus server on loopback must make
// none. (The server runs in its own thread, which is not counted.)
#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <new>

#include "fault_server.hpp"
#include "hal/modbus/modbus_field_bus.hpp"

// The replacement operator delete hands the block back to free(); after inlining, GCC
// sees free() on a pointer from operator new and warns, though the pair is consistent.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

namespace {
thread_local bool counting = false;
thread_local std::size_t allocations = 0;
}  // namespace

void* operator new(std::size_t size) {
  if (counting) {
    ++allocations;
  }
  if (void* p = std::malloc(size == 0 ? 1 : size)) {
    return p;
  }
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  return operator new(size);
}
// The nothrow forms too (std::stable_sort's temporary buffer uses them): every form that
// can pair with another must come from the same family.
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  if (counting) {
    ++allocations;
  }
  return std::malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept {
  return operator new(size, tag);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

using namespace excite::hal;
using namespace excite::hal::modbus;

TEST(ModbusNoAllocation, TheCounterSeesAnAllocation) {  // the probe works
  counting = true;
  allocations = 0;
  int* volatile escaped = new int(3);  // volatile: the compiler may not elide it
  counting = false;
  delete escaped;
  EXPECT_EQ(allocations, 1U);
}

TEST(ModbusNoAllocation, TheCounterSeesAllocationsInsideTheLibrary) {  // configure allocates
  excite::test::FaultServer server;
  ModbusConfig config;
  config.device.port = server.port();
  config.map.values.push_back(RegisterEntry{"pv", 0, 4, "float32", "ABCD", 0, 0, {}, {}});
  ModbusFieldBus bus;
  counting = true;
  allocations = 0;
  const bool configured = bus.configure(config).ok();
  counting = false;
  EXPECT_TRUE(configured);
  EXPECT_GT(allocations, 0U);
}

TEST(ModbusNoAllocation, ThousandExchangesAllocateNothing) {
  excite::test::FaultServer server;
  ModbusConfig config;
  config.device.port = server.port();
  config.device.response_timeout_ms = 2000;  // a slow tick on a shared machine is not the point
  for (std::uint32_t i = 0; i < 4; ++i) {
    config.map.setpoints.push_back(RegisterEntry{"sp", 2 * i, 16, "float32", "CDAB", 0, 0, {}, {}});
    config.map.values.push_back(
        RegisterEntry{"pv", 100 + 2 * i, 4, "float32", "DCBA", 0, 0, {}, {}});
  }
  config.map.values.push_back(RegisterEntry{"level", 200, 3, "uint16", "ABCD", 0.0, 100.0, {}, {}});
  config.map.heartbeat_address = 8;
  ModbusFieldBus bus;
  ASSERT_TRUE(bus.configure(config).ok());
  std::array<double, 4> setpoints{1.0, 2.0, 3.0, 4.0};
  std::array<double, 5> values{};

  counting = true;
  allocations = 0;
  int failures = 0;
  for (std::uint16_t tick = 0; tick < 1000; ++tick) {
    setpoints[0] = tick * 0.5;
    failures += bus.exchange(setpoints, tick, values) == StatusCode::ok ? 0 : 1;
  }
  counting = false;
  EXPECT_EQ(failures, 0) << bus.detail();
  EXPECT_EQ(allocations, 0U);
  EXPECT_EQ(server.holding(8), 999);
  EXPECT_EQ(bus.requests(), 3000U);  // FC16, FC03, FC04 per tick
}
