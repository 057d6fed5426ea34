#!/bin/sh
# Installs the Debian 12 packages voxkit needs. Idempotent: apt-get skips what is there.
# Run as root (or through sudo when it exists).
set -eu
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends \
    build-essential cmake pkg-config clang libclang-rt-14-dev python3 zlib1g-dev libdeflate-dev libzstd-dev \
    libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-tools spirv-tools \
    libglfw3-dev xvfb xauth \
    libopenvdb-dev libboost-dev libtbb-dev libimath-dev libopenvdb-tools \
    libtinygltf-dev libstb-dev nlohmann-json3-dev \
    libopenimageio-dev libpng-dev \
    libopenmpi-dev openmpi-bin \
    python3-matplotlib \
    libimgui-dev blender
