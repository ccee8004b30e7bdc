# Cross-compiling for arm64 (aarch64) with Debian's cross toolchain (crossbuild-essential-arm64)
# against the multiarch :arm64 libraries in /usr/lib/aarch64-linux-gnu; scripts/cross-arm64
# installs both and uses this file.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)

# Multiarch, not a sysroot: the arm64 libraries and their CMake configs live beside the host's
# under /usr, in the aarch64-linux-gnu subdirectories, which CMake searches once it knows the
# library architecture. The host's x86_64-linux-gnu directories are then never searched.
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
# pkg-config (libmodbus, tomlplusplus, libmosquitto, libsystemd): only the arm64 .pc files and
# the architecture-independent ones.
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig)

# Programs built for arm64 run under qemu's user-mode emulator. No -L /usr/aarch64-linux-gnu:
# the multiarch libc6:arm64 (installed with the :arm64 libraries) gives the loader at
# /lib/ld-linux-aarch64.so.1 and finds the libraries as an arm64 Debian would, while the cross
# toolchain's own copy of libc (an older build of 2.36) is only linked against. CMake uses the
# emulator for add_test() commands, and doctest_discover_tests lists a test program's cases
# through it after each build.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64-static)
