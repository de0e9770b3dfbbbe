# Cross build for 64-bit ARM (aarch64) Linux set-top boxes.
#
# Two ways to find the target's libraries:
#  - Debian multiarch (default): `toolchain/install-deps.sh --cross aarch64` installs the cross compiler and
#    the :arm64 -dev packages into /usr/lib/aarch64-linux-gnu.
#  - A sysroot: set DT_SYSROOT (cache variable or environment) to the SoC vendor's root file system.
# Tests run under qemu-user through CMAKE_CROSSCOMPILING_EMULATOR, so `ctest --preset aarch64` works on the host.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(DT_CROSS_TRIPLE aarch64-linux-gnu)
set(DT_CROSS_QEMU qemu-aarch64)

include(${CMAKE_CURRENT_LIST_DIR}/modules/DtCrossCommon.cmake)
