// A live camera as a source of frames stamped on the host clock (Unix seconds, the clock of the
// vehicle's odometry): the interface the tracker agent's live input reads, with the counters its
// health reports. Implementations: AravisCamera (GenICam: GigE Vision, USB3 Vision) and
// GstCamera (a GStreamer pipeline through OpenCV: V4L2/UVC, aravissrc, RTSP, files).
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "base/status.h"

namespace fleetloc::camera_io {

struct CapturedFrame {
  cv::Mat image;           // CV_8UC1, as the camera delivered it (raw or rectified)
  double t = 0.0;          // capture time, host clock (Unix seconds)
  double arrival_t = 0.0;  // when it reached us, host clock
};

struct CameraStats {
  long long frames = 0;          // complete frames delivered
  long long dropped = 0;         // incomplete or failed buffers, frames not convertible
  long long lost_packets = 0;    // GigE Vision packets never received (after resends)
  long long resent_packets = 0;  // GigE Vision packets that had to be asked for again
  // Frames withheld while the device clock's mapping to the host clock settles (its first
  // samples after an open or a clock restart), so no frame carries a capture time late by its
  // whole transfer delay (measured: 53 ms under load); not a drop.
  long long clock_settling = 0;
  std::string last_drop;  // why the last frame was dropped
};

class CameraSource {
 public:
  virtual ~CameraSource() = default;
  // Waits up to `timeout_s` for the next complete frame; nullopt when none came in time or the
  // frame was dropped (counted in stats()). Unavailable-style Internal error when the device is
  // gone: the caller closes this source and opens a new one later.
  virtual Result<std::optional<CapturedFrame>> Grab(double timeout_s) = 0;
  virtual CameraStats stats() const = 0;
  // What is open, for log lines ("aravis camera Fake_1 (127.0.0.1)").
  virtual std::string Describe() const = 0;
};

// After an open or a device clock restart, frames are stamped once the clock mapping has seen this
// many (the frame itself included): the ones before only feed it (CameraStats::clock_settling),
// and every stamped frame's offset is the smallest delay of at least three.
inline constexpr long long kClockSettleFrames = 3;

// Now on the host clock, Unix seconds.
double HostNow();

}  // namespace fleetloc::camera_io
