# SPDX-License-Identifier: MIT
# Cross toolchain: Debian 12's aarch64-linux-gnu cross compiler, target libraries from Debian
# multiarch (arm64: apt-get install libmodbus-dev:arm64 ..., toolchain/dev installs them).
# Tests run under qemu-user (CMAKE_CROSSCOMPILING_EMULATOR), so plain ctest runs them.
# Only the target is described here: no project flags (those live in CMakeLists.txt).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

# Multiarch: target libraries live in /usr/lib/aarch64-linux-gnu, arch-independent headers and
# CMake packages in /usr/include and /usr/share. The cross compiler's own root comes first.
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu /)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# pkg-config (libmodbus): the target's .pc files only, never the build machine's.
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig)
set(ENV{PKG_CONFIG_PATH} "")

# Target libraries that multiarch could not install beside the build machine's (a version
# skew: toolchain/dev's unpack_skewed unpacks them here instead). Searched like /; its
# libraries are found by qemu through -L (qemu looks under the prefix first, then /).
get_filename_component(EXCITE_TARGET_ROOT "${CMAKE_CURRENT_LIST_DIR}/../build/target-root/arm64"
                       ABSOLUTE)
set(EXCITE_QEMU_PREFIX "")
if(EXISTS "${EXCITE_TARGET_ROOT}")
  list(APPEND CMAKE_FIND_ROOT_PATH "${EXCITE_TARGET_ROOT}")
  set(ENV{PKG_CONFIG_LIBDIR} "${EXCITE_TARGET_ROOT}/usr/lib/aarch64-linux-gnu/pkgconfig:$ENV{PKG_CONFIG_LIBDIR}")
  set(EXCITE_QEMU_PREFIX -L "${EXCITE_TARGET_ROOT}")
endif()

# qemu-user runs target executables (tests, gtest discovery). The target's own loader, libc and
# libstdc++ come from multiarch (libc6:ARCH, libstdc++6:ARCH, pulled in by the -dev packages),
# where qemu finds them without -L.
find_program(EXCITE_QEMU_arm64 qemu-aarch64 REQUIRED)
set(CMAKE_CROSSCOMPILING_EMULATOR ${EXCITE_QEMU_arm64} ${EXCITE_QEMU_PREFIX})
