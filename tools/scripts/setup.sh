#!/usr/bin/env bash
# Installs fleetloc's Debian 12 build dependencies (only those missing) and builds the project
# into build/ (Release, ccache when present). Used by both README commands and by CI.
set -euo pipefail
cd "$(dirname "$0")/../.."

PACKAGES=(build-essential cmake ninja-build pkg-config ccache libopencv-dev libeigen3-dev
          libsqlite3-dev sqlite3 libspdlog-dev nlohmann-json3-dev libcpp-httplib-dev libcli11-dev
          cyclonedds-dev cyclonedds-tools libgtest-dev libbenchmark-dev libpng-dev systemd curl
          clang libclang-rt-14-dev
          clang-tidy clang-format  # tools/scripts/check_tidy.sh and check_format.sh (.clang-tidy, .clang-format)
          prometheus-cpp-dev  # /metrics of every service (common/metrics/)
          libmosquitto-dev mosquitto mosquitto-clients  # VDA 5050 over MQTT (supervisor, its test)
          python3-jsonschema  # validates the VDA 5050 messages in tests/vda5050_mqtt_test.cpp
          gdal-bin  # gdalinfo reads back fleetctl mosaic export's world file (tests/cli_mosaic_export_test)
          libsystemd-dev  # sd_notify: Type=notify readiness and the watchdog (common/runtime/service_notify.h)
          libjs-leaflet libjs-chart.js  # the dashboard's map and plots, served by the supervisor at /vendor/
          debootstrap  # the opt-in package install test (tests/deploy/deb_packages_test.sh install)
          libaravis-dev libusb-1.0-0-dev  # GenICam cameras (common/camera_io/aravis_camera.*); aravis-0.8.pc needs libusb's .pc
          aravis-tools  # arv-tool / arv-fake-gv-camera-0.8: look at a camera by hand (docs/vehicle_integration.md)
          libgstreamer1.0-dev libgstreamer-plugins-base1.0-dev gstreamer1.0-plugins-base gstreamer1.0-plugins-good  # GStreamer camera pipelines read from their appsink (gstreamer-app, -video; multifilesrc, pngdec, v4l2src, udpsrc)
          libfastrtps-dev fastddsgen  # the ROS 2 interop test node (tests/ros2_nav_stack_node.cpp), as rmw_fastrtps sees the wire; fastddsgen also checks idl/fleetloc.idl (tests/idl/)
          chromium)  # chromium: the dashboard's browser test (tests/browser/)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# Node.js for the browser test: Debian's nodejs and npm unless a node with npm is already there.
if ! command -v npm >/dev/null 2>&1; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends nodejs npm
fi

BUILD_TYPE="${FLEETLOC_BUILD_TYPE:-Release}"
# FLEETLOC_WERROR=ON (CI, through run_tests.sh) makes every compiler warning an error. Unset, the
# build keeps its cached choice: the fleet command after the tests does not rebuild everything.
WERROR_ARG=()
[[ -n "${FLEETLOC_WERROR:-}" ]] && WERROR_ARG=(-DFLEETLOC_WERROR="$FLEETLOC_WERROR")
cmake --preset release -DCMAKE_BUILD_TYPE="$BUILD_TYPE" "${WERROR_ARG[@]}" >/dev/null  # CMakePresets.json
cmake --build --preset release -j "$(nproc)"
# The browser test's Node packages (playwright-core, pinned by tests/browser/package-lock.json).
tests/browser/install_deps.sh build/browser
