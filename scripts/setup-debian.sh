#!/usr/bin/env bash
# Installs every Debian 12 package wetdem needs to build, test and run on lavapipe.
# Idempotent: packages already present are left alone. Run as root (or with sudo available).
set -euo pipefail

PKGS=(
  build-essential cmake ninja-build pkg-config git
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  glslang-tools spirv-tools
  libglm-dev libtinygltf-dev nlohmann-json3-dev libstb-dev
  libgtest-dev libgmock-dev
  libtomlplusplus-dev libcli11-dev libfmt-dev libeigen3-dev
  clang-format
  python3-matplotlib libeigen3-dev   # figures (plot_run.py, plot_study.py, plot_diagnosis.py), emulator
  slurm-wlm munge                    # the real single-node Slurm test of `wetdem study slurm`
)

missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PKGS[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
