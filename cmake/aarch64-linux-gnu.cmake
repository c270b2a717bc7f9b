# Cross-building for 64-bit ARM Linux with Debian's cross compiler and the arm64 packages of
# the libraries (multiarch: dpkg --add-architecture arm64); deploy/arm64-check.sh installs both.
# Test programs run through qemu's user-mode emulator, for gtest discovery and for ctest,
# with the arm64 loader and C library that multiarch installs (no -L prefix: the cross
# toolchain's own loader beside a newer multiarch libc hangs in pthread_create).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
# Multiarch keeps arm64 libraries beside the host's, under lib/aarch64-linux-gnu: searched
# through the library architecture rather than a separate root.
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig")
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64)
