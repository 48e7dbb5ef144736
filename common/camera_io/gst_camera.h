// A camera behind a GStreamer pipeline, read from its appsink (gstreamer-app): any V4L2/UVC
// camera (`v4l2src ...`), a GenICam camera through aravissrc, an RTSP or UDP stream, or frames from
// files (`multifilesrc ...`); the pipeline must contain an appsink. Frames are stamped with the
// buffer's timestamp (PTS, for a live source its capture time) on the pipeline's clock mapped to
// the host clock, with the arrival time when the buffer carries none, as a device clock (a
// camera's own timestamps) mapped to the host clock, or on the frame-rate grid of a recorded run.
// Grab waits at most its timeout, so a stalled pipeline is seen (and reopened by the live input).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "camera_io/camera_source.h"
#include "timing/clock_mapper.h"

typedef struct _GstElement GstElement;
typedef struct _GstAppSink GstAppSink;
typedef struct _GstSample GstSample;
typedef struct _GstBuffer GstBuffer;
typedef struct _GstSegment GstSegment;

namespace fleetloc::camera_io {

struct GstOptions {
  std::string pipeline;  // a gst-launch description with an appsink
  // "buffer": the buffer's PTS as a time on the pipeline clock (base time + running time), mapped
  // to the host clock by reading both clocks at once (never later than the arrival; the arrival
  // when the buffer has no PTS); "device": the PTS as the camera's own clock (aravissrc without
  // do-timestamp stamps each buffer with the camera's timestamp since its first frame), mapped to
  // the host clock by the smallest arrival delay (timing::ClockMapper; the frames
  // before the mapping has seen kClockSettleFrames after a start or a clock restart only feed
  // it and are withheld; a buffer without PTS is dropped); "arrival": when it reached us;
  // "frame_rate": the n-th frame (from 0) at epoch_s + n / the caps' framerate, as multifilesrc
  // stamps its buffers (files of a recorded run whose first frame's time is known: its frames keep
  // their recorded times).
  std::string timestamps = "buffer";
  double epoch_s = 0.0;
};

Status Validate(const GstOptions& options);

// The host time of a buffer stamped `capture_clock_ns` on a clock that read `clock_now_ns` when
// the host clock read `host_now_s`; never later than host_now_s.
double PipelineClockToHost(unsigned long long capture_clock_ns, unsigned long long clock_now_ns,
                           double host_now_s);

class GstCamera : public CameraSource {
 public:
  // Starts the pipeline (sets it PLAYING). Internal when GStreamer cannot parse or start it (bad
  // description, missing plugin, no appsink), with the pipeline's own error.
  static Result<std::unique_ptr<GstCamera>> Open(const GstOptions& options);
  ~GstCamera() override;  // stops the pipeline

  // Waits up to timeout_s for a sample. nullopt on timeout or a frame in a format that is neither
  // 8-bit gray nor 8-bit colour (counted as dropped); Internal at the end of the stream or when
  // the pipeline posted an error.
  Result<std::optional<CapturedFrame>> Grab(double timeout_s) override;
  CameraStats stats() const override { return stats_; }
  std::string Describe() const override { return "gstreamer pipeline '" + options_.pipeline + "'"; }

 private:
  explicit GstCamera(GstOptions options) : options_(std::move(options)) {}
  Status Start();
  // The first error the pipeline posted on its bus (Ok when none).
  Status PipelineError() const;
  // The sample's image as CV_8UC1 (nullopt, counted, when its format is not supported).
  std::optional<cv::Mat> Image(GstSample* sample);
  // The capture time on the host clock; nullopt for a frame withheld or dropped (counted).
  std::optional<double> CaptureTime(GstSample* sample, double arrival_t);
  double PipelineTime(GstBuffer* buffer, const GstSegment* segment, double arrival_t) const;
  std::optional<double> DeviceTime(GstBuffer* buffer, double arrival_t);

  GstOptions options_;
  GstElement* pipeline_ = nullptr;
  GstAppSink* sink_ = nullptr;
  CameraStats stats_;
  double fps_ = 0.0;           // the caps' framerate (frame_rate timestamps)
  long long read_ = 0;         // samples pulled since the pipeline started
  timing::ClockMapper clock_;  // device timestamps
};

}  // namespace fleetloc::camera_io
