#!/usr/bin/env bash
# Install (or print the command to install) the Debian/Ubuntu packages NavVerse needs.
#   librecast-dev          RecastNavigation headers and libraries for the navmesh extension
#   libembree-dev          Embree 3 headers and library for the camera's ray caster
#   libusb-1.0-0 libudev1  loaded by open3d's wheel
#   libgl1 libegl1 libx11-6 libgomp1  loaded by open3d's and pybullet's wheels
#   g++ python3-dev python3-venv make  build the C++ extension and the virtual environment
#   chromium               headless screenshots of report.html (scripts/report_screenshot.py, its test)
set -euo pipefail
PACKAGES=(librecast-dev libembree-dev libusb-1.0-0 libudev1 libgl1 libegl1 libx11-6 libgomp1 g++ make python3-dev python3-venv chromium)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -eq 0 ]; then
  echo "system packages: all present"
  exit 0
fi
if ! command -v apt-get >/dev/null 2>&1; then
  echo "system packages missing (${missing[*]}) and apt-get is not available: install their equivalents by hand" >&2
  exit 1
fi
if [ "$(id -u)" -eq 0 ]; then
  SUDO=""
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
  SUDO="sudo"
else
  echo "system packages missing: ${missing[*]}" >&2
  echo "run this once, then 'make setup' again:" >&2
  echo "  sudo apt-get update && sudo apt-get install -y ${missing[*]}" >&2
  exit 1
fi
echo "installing system packages: ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}"
