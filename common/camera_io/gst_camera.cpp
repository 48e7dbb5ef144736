// GstCamera: a GStreamer pipeline's appsink behind CameraSource.
#include "camera_io/gst_camera.h"

#include <gst/app/gstappsink.h>
#include <gst/gst.h>
#include <gst/video/video.h>

#include <cmath>
#include <mutex>
#include <opencv2/imgproc.hpp>

namespace fleetloc::camera_io {
namespace {

// GStreamer is initialized once per process; false (with the reason) when it cannot be.
Status InitGstreamer() {
  static std::once_flag once;
  static std::string error;
  std::call_once(once, [] {
    GError* e = nullptr;
    if (!gst_init_check(nullptr, nullptr, &e)) {
      error = e ? e->message : "gst_init failed";
      if (e) g_error_free(e);
    }
  });
  return error.empty() ? Status::Ok() : Internal("gstreamer: " + error);
}

// The pipeline's first appsink (a new reference), or null.
GstAppSink* FindAppSink(GstElement* pipeline) {
  if (GST_IS_APP_SINK(pipeline)) return GST_APP_SINK(gst_object_ref(pipeline));
  if (!GST_IS_BIN(pipeline)) return nullptr;
  GstIterator* it = gst_bin_iterate_recurse(GST_BIN(pipeline));
  GValue item = G_VALUE_INIT;
  GstAppSink* found = nullptr;
  while (!found && gst_iterator_next(it, &item) == GST_ITERATOR_OK) {
    GstElement* element = GST_ELEMENT(g_value_get_object(&item));
    if (GST_IS_APP_SINK(element)) found = GST_APP_SINK(gst_object_ref(element));
    g_value_reset(&item);
  }
  g_value_unset(&item);
  gst_iterator_free(it);
  return found;
}

// A packed 8-bit format and the conversion to gray; -1 when not supported.
int GrayConversion(GstVideoFormat format, int* type) {
  switch (format) {
    case GST_VIDEO_FORMAT_GRAY8:
      *type = CV_8UC1;
      return 0;
    case GST_VIDEO_FORMAT_BGR:
      *type = CV_8UC3;
      return cv::COLOR_BGR2GRAY;
    case GST_VIDEO_FORMAT_RGB:
      *type = CV_8UC3;
      return cv::COLOR_RGB2GRAY;
    case GST_VIDEO_FORMAT_BGRx:
    case GST_VIDEO_FORMAT_BGRA:
      *type = CV_8UC4;
      return cv::COLOR_BGRA2GRAY;
    case GST_VIDEO_FORMAT_RGBx:
    case GST_VIDEO_FORMAT_RGBA:
      *type = CV_8UC4;
      return cv::COLOR_RGBA2GRAY;
    default:
      return -1;
  }
}

}  // namespace

Status Validate(const GstOptions& o) {
  if (o.pipeline.find("appsink") == std::string::npos) {
    return InvalidInput("field 'gstreamer.pipeline': must end in an appsink");
  }
  if (o.timestamps != "buffer" && o.timestamps != "device" && o.timestamps != "arrival" &&
      o.timestamps != "frame_rate") {
    return InvalidInput(
        "field 'gstreamer.timestamps': must be buffer, device, arrival or frame_rate");
  }
  if (!std::isfinite(o.epoch_s)) return InvalidInput("field 'gstreamer.epoch_s': must be finite");
  return Status::Ok();
}

double PipelineClockToHost(unsigned long long capture_clock_ns, unsigned long long clock_now_ns,
                           double host_now_s) {
  const double age_s =
      (static_cast<double>(clock_now_ns) - static_cast<double>(capture_clock_ns)) * 1e-9;
  return host_now_s - std::max(0.0, age_s);
}

Result<std::unique_ptr<GstCamera>> GstCamera::Open(const GstOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(Validate(options));
  FLEETLOC_RETURN_IF_ERROR(InitGstreamer());
  std::unique_ptr<GstCamera> cam(new GstCamera(options));
  FLEETLOC_RETURN_IF_ERROR(cam->Start());
  return cam;
}

Status GstCamera::Start() {
  GError* error = nullptr;
  pipeline_ = gst_parse_launch(options_.pipeline.c_str(), &error);
  if (error != nullptr) {
    const std::string message = error->message;
    g_error_free(error);
    return Internal("gstreamer: cannot parse pipeline '" + options_.pipeline + "': " + message);
  }
  if (pipeline_ == nullptr) return Internal("gstreamer: cannot parse '" + options_.pipeline + "'");
  gst_object_ref_sink(pipeline_);
  sink_ = FindAppSink(pipeline_);
  if (sink_ == nullptr)
    return Internal("gstreamer: pipeline '" + options_.pipeline + "' has no appsink");
  // Not waited for: a live sink completes the change only with its first buffer, which may be
  // long in coming (a stalled source); later failures are posted on the bus and Grab reports them.
  if (gst_element_set_state(pipeline_, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE) {
    const Status posted = PipelineError();
    return Internal("gstreamer: cannot start pipeline '" + options_.pipeline + "'" +
                    (posted.ok() ? "" : ": " + posted.message()));
  }
  return Status::Ok();
}

GstCamera::~GstCamera() {
  if (pipeline_ != nullptr) {
    gst_element_set_state(pipeline_, GST_STATE_NULL);
    gst_object_unref(pipeline_);
  }
  if (sink_ != nullptr) gst_object_unref(sink_);
}

Status GstCamera::PipelineError() const {
  GstBus* bus = gst_element_get_bus(pipeline_);
  GstMessage* message = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR);
  gst_object_unref(bus);
  if (message == nullptr) return Status::Ok();
  GError* error = nullptr;
  gchar* debug = nullptr;
  gst_message_parse_error(message, &error, &debug);
  const char* source = message->src ? GST_OBJECT_NAME(message->src) : "pipeline";
  std::string text = std::string(source) + ": " + (error ? error->message : "error");
  if (error) g_error_free(error);
  g_free(debug);
  gst_message_unref(message);
  return Internal(text);
}

Result<std::optional<CapturedFrame>> GstCamera::Grab(double timeout_s) {
  const GstClockTime timeout = static_cast<GstClockTime>(std::max(0.0, timeout_s) * GST_SECOND);
  GstSample* sample = gst_app_sink_try_pull_sample(sink_, timeout);
  if (sample == nullptr) {
    if (Status error = PipelineError(); !error.ok())
      return Internal(Describe() + ": " + error.message());
    if (gst_app_sink_is_eos(sink_)) return Internal(Describe() + ": end of stream");
    return std::optional<CapturedFrame>();  // nothing within the timeout
  }
  ++read_;  // samples pulled since the pipeline started, dropped or not
  CapturedFrame frame;
  frame.arrival_t = HostNow();
  std::optional<cv::Mat> image = Image(sample);
  std::optional<double> t;
  if (image) t = CaptureTime(sample, frame.arrival_t);
  gst_sample_unref(sample);
  if (!image || !t) return std::optional<CapturedFrame>();
  frame.t = *t;
  if (options_.timestamps == "frame_rate" && !(fps_ > 0))
    return Internal(Describe() + ": no framerate in its caps (gstreamer.timestamps frame_rate)");
  frame.image = std::move(*image);
  ++stats_.frames;
  return std::optional<CapturedFrame>(std::move(frame));
}

std::optional<cv::Mat> GstCamera::Image(GstSample* sample) {
  GstVideoInfo info;
  GstCaps* caps = gst_sample_get_caps(sample);
  GstBuffer* buffer = gst_sample_get_buffer(sample);
  int type = 0, conversion = -1;
  if (caps != nullptr && buffer != nullptr && gst_video_info_from_caps(&info, caps))
    conversion = GrayConversion(GST_VIDEO_INFO_FORMAT(&info), &type);
  if (conversion < 0) {
    ++stats_.dropped;
    gchar* text = caps ? gst_caps_to_string(caps) : nullptr;
    stats_.last_drop = "sample of caps " + std::string(text ? text : "none") +
                       " (want video/x-raw GRAY8, BGR, RGB, BGRx or RGBx)";
    g_free(text);
    return std::nullopt;
  }
  if (fps_ <= 0 && info.fps_d > 0) fps_ = static_cast<double>(info.fps_n) / info.fps_d;
  GstMapInfo map;
  if (!gst_buffer_map(buffer, &map, GST_MAP_READ)) {
    ++stats_.dropped;
    stats_.last_drop = "buffer cannot be mapped";
    return std::nullopt;
  }
  const cv::Mat view(GST_VIDEO_INFO_HEIGHT(&info), GST_VIDEO_INFO_WIDTH(&info), type, map.data,
                     GST_VIDEO_INFO_PLANE_STRIDE(&info, 0));
  cv::Mat gray;
  if (map.size < GST_VIDEO_INFO_SIZE(&info)) {
    ++stats_.dropped;
    stats_.last_drop = "buffer smaller than its caps say";
  } else if (conversion == 0) {
    gray = view.clone();
  } else {
    cv::cvtColor(view, gray, conversion);
  }
  gst_buffer_unmap(buffer, &map);
  if (gray.empty()) return std::nullopt;
  return gray;
}

std::optional<double> GstCamera::CaptureTime(GstSample* sample, double arrival_t) {
  if (options_.timestamps == "frame_rate") {
    return options_.epoch_s + static_cast<double>(read_ - 1) / fps_;  // fps_ > 0: checked by Grab
  }
  if (options_.timestamps == "arrival") return arrival_t;
  GstBuffer* buffer = gst_sample_get_buffer(sample);
  if (options_.timestamps == "device") return DeviceTime(buffer, arrival_t);
  return PipelineTime(buffer, gst_sample_get_segment(sample), arrival_t);
}

std::optional<double> GstCamera::DeviceTime(GstBuffer* buffer, double arrival_t) {
  if (!GST_BUFFER_PTS_IS_VALID(buffer)) {
    ++stats_.dropped;
    stats_.last_drop = "buffer without a timestamp (gstreamer.timestamps device)";
    return std::nullopt;
  }
  const double t = clock_.Map(static_cast<double>(GST_BUFFER_PTS(buffer)) * 1e-9, arrival_t);
  if (clock_.samples() < kClockSettleFrames) {
    ++stats_.clock_settling;
    return std::nullopt;
  }
  return t;
}

double GstCamera::PipelineTime(GstBuffer* buffer, const GstSegment* segment,
                               double arrival_t) const {
  if (!GST_BUFFER_PTS_IS_VALID(buffer) || segment == nullptr) return arrival_t;
  const GstClockTime running =
      gst_segment_to_running_time(segment, GST_FORMAT_TIME, GST_BUFFER_PTS(buffer));
  GstClock* clock = gst_element_get_clock(pipeline_);
  if (!GST_CLOCK_TIME_IS_VALID(running) || clock == nullptr) {
    if (clock) gst_object_unref(clock);
    return arrival_t;
  }
  // Both clocks read at once: the pipeline clock around the host clock, again if preempted.
  GstClockTime before = 0, after = 0;
  double host_now = 0;
  for (int attempt = 0; attempt < 3; ++attempt) {
    before = gst_clock_get_time(clock);
    host_now = HostNow();
    after = gst_clock_get_time(clock);
    if (after - before < 20 * GST_USECOND) break;
  }
  gst_object_unref(clock);
  const GstClockTime clock_now = before + (after - before) / 2;
  const GstClockTime base = gst_element_get_base_time(pipeline_);
  return std::min(arrival_t, PipelineClockToHost(base + running, clock_now, host_now));
}

}  // namespace fleetloc::camera_io
