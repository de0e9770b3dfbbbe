# Cross build for 32-bit ARM hard-float (armhf) Linux set-top boxes.
# Same scheme as aarch64-linux-gnu.cmake: Debian multiarch (`install-deps.sh --cross armhf`) or DT_SYSROOT.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR armv7l)
set(DT_CROSS_TRIPLE arm-linux-gnueabihf)
set(DT_CROSS_QEMU qemu-arm)

include(${CMAKE_CURRENT_LIST_DIR}/modules/DtCrossCommon.cmake)
