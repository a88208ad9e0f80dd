# Cross build for 64-bit ARM Linux (aarch64: Raspberry Pi 4/5 class computers) with Debian's cross toolchain
# (crossbuild-essential-arm64) and the :arm64 libraries installed beside the host's (dpkg --add-architecture arm64):
# scripts/install-deps.sh arm64, scripts/cross-build.sh, docs/packaging.md "64-bit ARM" (issue 45).
#
#   cmake -G Ninja -S . -B build/arm64 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake \
#         -DROCKWATCH_CROSS_SYSROOT=$PWD/build/arm64/sysroot ...
#
# Debian's multiarch layout makes the host itself the sysroot: arm64 libraries are in /usr/lib/aarch64-linux-gnu, found
# through CMAKE_LIBRARY_ARCHITECTURE (taken from the compiler) and aarch64-linux-gnu-pkg-config; the header-only
# libraries (Eigen, CLI11, nlohmann-json, Boost) and lcm-gen (a build-time program) are the host's.
# ROCKWATCH_CROSS_SYSROOT (optional): a directory with arm64 packages unpacked by `dpkg -x` that cannot be installed
# beside the host's (liblcm1 and liblcm-dev are Multi-Arch: no); its pkg-config files come first.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(PKG_CONFIG_EXECUTABLE aarch64-linux-gnu-pkg-config CACHE FILEPATH "pkg-config for aarch64-linux-gnu")
# Programs that run at build time (the man pages from --help, try_run) run under user-mode QEMU; the arm64 dynamic
# loader and libraries are the host's multiarch ones (libc6:arm64), so no -L is needed.
find_program(ROCKWATCH_QEMU_AARCH64 qemu-aarch64)
if(ROCKWATCH_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${ROCKWATCH_QEMU_AARCH64})
endif()
set(CMAKE_TRY_COMPILE_PLATFORM_VARIABLES ROCKWATCH_CROSS_SYSROOT)
if(ROCKWATCH_CROSS_SYSROOT)
  if(NOT IS_DIRECTORY "${ROCKWATCH_CROSS_SYSROOT}/usr/lib/aarch64-linux-gnu")
    message(FATAL_ERROR "ROCKWATCH_CROSS_SYSROOT=${ROCKWATCH_CROSS_SYSROOT}: expected a directory with "
      "usr/lib/aarch64-linux-gnu (arm64 packages unpacked with dpkg -x: scripts/install-deps.sh arm64)")
  endif()
  set(ENV{PKG_CONFIG_PATH} "${ROCKWATCH_CROSS_SYSROOT}/usr/lib/aarch64-linux-gnu/pkgconfig")
  list(APPEND CMAKE_PREFIX_PATH "${ROCKWATCH_CROSS_SYSROOT}/usr")
endif()
