// A GenICam camera (GigE Vision, USB3 Vision) through Aravis: opened by device id, serial or IP
// address, configured (pixel format, region, exposure, gain, frame rate or trigger), streaming
// into a small buffer pool. Device timestamps are mapped to the host clock (ClockMapper);
// incomplete buffers and lost packets are counted; a lost control channel makes Grab fail so the
// caller reopens the camera.
#pragma once

#include <atomic>
#include <memory>
#include <string>

#include "camera_io/camera_source.h"
#include "timing/clock_mapper.h"

typedef struct _ArvCamera ArvCamera;
typedef struct _ArvStream ArvStream;

namespace fleetloc::camera_io {

struct AravisOptions {
  std::string device;  // Aravis device id, serial number or IP address; empty: first
  std::string pixel_format = "Mono8";  // a PFNC name IsSupportedPixelFormat accepts
  int region_x = 0, region_y = 0;
  int region_width = 0, region_height = 0;  // 0: leave the camera's
  double exposure_us = 0.0;                 // 0: leave the camera's
  double gain = -1.0;                       // < 0: leave the camera's
  double frame_rate_hz = 0.0;               // free running at this rate; 0: leave the camera's
  std::string trigger;  // empty: free running; "Software", "Line0", ...: hardware trigger
  std::string timestamps = "device";  // "device" (mapped to the host clock) or "arrival"
  int packet_size = 0;                // GigE Vision packet size in bytes; 0: negotiated by Aravis
  int buffers = 8;                    // stream buffer pool
};

// InvalidInput naming the field ("aravis.pixel_format: ...").
Status Validate(const AravisOptions& options);

class AravisCamera : public CameraSource {
 public:
  // Opens and starts the camera. NotFound when no such device answers; Internal naming the
  // feature the camera refused.
  static Result<std::unique_ptr<AravisCamera>> Open(const AravisOptions& options);
  ~AravisCamera() override;

  Result<std::optional<CapturedFrame>> Grab(double timeout_s) override;
  CameraStats stats() const override;
  std::string Describe() const override { return description_; }

 private:
  explicit AravisCamera(const AravisOptions& options) : options_(options) {}
  Status Configure();
  Status StartStream();
  // The buffer's image (dropped and counted when incomplete or not convertible).
  std::optional<CapturedFrame> Convert(void* buffer);

  AravisOptions options_;
  std::string description_;
  std::string pixel_format_;  // the camera's, read once after configuration
  ArvCamera* camera_ = nullptr;
  ArvStream* stream_ = nullptr;
  unsigned long control_lost_handler_ = 0;
  std::atomic<bool> control_lost_{false};
  timing::ClockMapper clock_;
  CameraStats stats_;
};

}  // namespace fleetloc::camera_io
