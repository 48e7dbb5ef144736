// Aravis (GObject C API) behind CameraSource: every GError turned into a Status naming the step.
#include "camera_io/aravis_camera.h"

#include <arv.h>

#include <chrono>

#include "camera_io/pixel_format.h"

namespace fleetloc::camera_io {
namespace {

// Runs an Aravis call taking a trailing GError**; Internal "<what>: <message>" if it failed.
template <typename Fn>
Status Checked(const std::string& what, Fn&& fn) {
  GError* error = nullptr;
  fn(&error);
  if (error == nullptr) return Status::Ok();
  const std::string message = what + ": " + error->message;
  g_clear_error(&error);
  return Internal(message);
}

}  // namespace

double HostNow() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

Status Validate(const AravisOptions& o) {
  auto bad = [](const std::string& field, const std::string& what) {
    return InvalidInput("field 'aravis." + field + "': " + what);
  };
  if (!IsSupportedPixelFormat(o.pixel_format))
    return bad("pixel_format", o.pixel_format + " is not supported");
  if (o.region_x < 0 || o.region_y < 0 || o.region_width < 0 || o.region_height < 0) {
    return bad("region", "must be 4 non-negative integers x, y, width, height");
  }
  if (!(o.exposure_us >= 0)) return bad("exposure_us", "must be >= 0");
  if (!(o.frame_rate_hz >= 0 && o.frame_rate_hz <= 1000))
    return bad("frame_rate_hz", "must be in [0, 1000]");
  if (!o.trigger.empty() && o.frame_rate_hz > 0) return bad("trigger", "excludes frame_rate_hz");
  if (o.timestamps != "device" && o.timestamps != "arrival")
    return bad("timestamps", "must be device or arrival");
  if (o.packet_size < 0 || o.packet_size > 16384)
    return bad("packet_size", "must be in [0, 16384]");
  if (o.buffers < 2 || o.buffers > 64) return bad("buffers", "must be in [2, 64]");
  return Status::Ok();
}

Result<std::unique_ptr<AravisCamera>> AravisCamera::Open(const AravisOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(Validate(options));
  std::unique_ptr<AravisCamera> cam(new AravisCamera(options));
  const char* name = options.device.empty() ? nullptr : options.device.c_str();
  const std::string which =
      options.device.empty() ? "the first camera" : "camera '" + options.device + "'";
  GError* error = nullptr;
  cam->camera_ = arv_camera_new(name, &error);
  if (cam->camera_ == nullptr) {
    const std::string message = which + ": " + (error ? error->message : "not found");
    g_clear_error(&error);
    return NotFound("aravis: " + message);
  }
  ArvDevice* device = arv_camera_get_device(cam->camera_);
  cam->control_lost_handler_ = g_signal_connect_swapped(
      device, "control-lost",
      G_CALLBACK(+[](AravisCamera* self) { self->control_lost_.store(true); }), cam.get());
  const char* model = arv_camera_get_model_name(cam->camera_, nullptr);
  cam->description_ = "aravis camera " + std::string(model ? model : "?") + " (" +
                      (options.device.empty() ? "first found" : options.device) + ")";
  FLEETLOC_RETURN_IF_ERROR(cam->Configure());
  FLEETLOC_RETURN_IF_ERROR(cam->StartStream());
  return cam;
}

Status AravisCamera::Configure() {
  const AravisOptions& o = options_;
  ArvCamera* c = camera_;
  FLEETLOC_RETURN_IF_ERROR(Checked("aravis: pixel format " + o.pixel_format, [&](GError** e) {
    arv_camera_set_pixel_format_from_string(c, o.pixel_format.c_str(), e);
  }));
  if (o.region_width > 0 && o.region_height > 0) {
    FLEETLOC_RETURN_IF_ERROR(Checked("aravis: region", [&](GError** e) {
      arv_camera_set_region(c, o.region_x, o.region_y, o.region_width, o.region_height, e);
    }));
  }
  if (o.exposure_us > 0) {
    FLEETLOC_RETURN_IF_ERROR(Checked("aravis: exposure", [&](GError** e) {
      arv_camera_set_exposure_time(c, o.exposure_us, e);
    }));
  }
  if (o.gain >= 0) {
    FLEETLOC_RETURN_IF_ERROR(
        Checked("aravis: gain", [&](GError** e) { arv_camera_set_gain(c, o.gain, e); }));
  }
  FLEETLOC_RETURN_IF_ERROR(Checked("aravis: acquisition mode", [&](GError** e) {
    arv_camera_set_acquisition_mode(c, ARV_ACQUISITION_MODE_CONTINUOUS, e);
  }));
  if (!o.trigger.empty()) {
    FLEETLOC_RETURN_IF_ERROR(Checked("aravis: trigger " + o.trigger, [&](GError** e) {
      arv_camera_set_trigger(c, o.trigger.c_str(), e);
    }));
  } else if (o.frame_rate_hz > 0) {
    FLEETLOC_RETURN_IF_ERROR(Checked("aravis: frame rate", [&](GError** e) {
      arv_camera_set_frame_rate(c, o.frame_rate_hz, e);
    }));
  }
  if (arv_camera_is_gv_device(c) && o.packet_size > 0) {
    FLEETLOC_RETURN_IF_ERROR(Checked("aravis: packet size", [&](GError** e) {
      arv_camera_gv_set_packet_size(c, o.packet_size, e);
    }));
  }
  return Status::Ok();
}

Status AravisCamera::StartStream() {
  GError* error = nullptr;
  stream_ = arv_camera_create_stream(camera_, nullptr, nullptr, &error);
  if (stream_ == nullptr) {
    const std::string message = std::string("aravis: stream: ") + (error ? error->message : "?");
    g_clear_error(&error);
    return Internal(message);
  }
  const char* format = arv_camera_get_pixel_format_as_string(camera_, nullptr);  // as set
  pixel_format_ = format ? format : "?";
  guint payload = 0;
  FLEETLOC_RETURN_IF_ERROR(Checked(
      "aravis: payload size", [&](GError** e) { payload = arv_camera_get_payload(camera_, e); }));
  for (int i = 0; i < options_.buffers; ++i)
    arv_stream_push_buffer(stream_, arv_buffer_new(payload, nullptr));
  return Checked("aravis: start acquisition",
                 [&](GError** e) { arv_camera_start_acquisition(camera_, e); });
}

AravisCamera::~AravisCamera() {
  if (camera_ != nullptr) {
    if (!control_lost_.load()) arv_camera_stop_acquisition(camera_, nullptr);
    g_signal_handler_disconnect(arv_camera_get_device(camera_), control_lost_handler_);
  }
  if (stream_ != nullptr) g_object_unref(stream_);
  if (camera_ != nullptr) g_object_unref(camera_);
}

Result<std::optional<CapturedFrame>> AravisCamera::Grab(double timeout_s) {
  if (control_lost_.load()) return Internal(description_ + ": control channel lost (device gone)");
  ArvBuffer* buffer = arv_stream_timeout_pop_buffer(stream_, static_cast<guint64>(timeout_s * 1e6));
  if (buffer == nullptr) return std::optional<CapturedFrame>();
  std::optional<CapturedFrame> frame = Convert(buffer);
  arv_stream_push_buffer(stream_, buffer);
  return frame;
}

std::optional<CapturedFrame> AravisCamera::Convert(void* opaque) {
  ArvBuffer* buffer = static_cast<ArvBuffer*>(opaque);
  const ArvBufferStatus status = arv_buffer_get_status(buffer);
  if (status != ARV_BUFFER_STATUS_SUCCESS) {
    ++stats_.dropped;
    stats_.last_drop = "buffer status " + std::to_string(static_cast<int>(status)) +
                       (status == ARV_BUFFER_STATUS_MISSING_PACKETS ? " (missing packets)" : "");
    return std::nullopt;
  }
  size_t size = 0;
  const void* data = arv_buffer_get_data(buffer, &size);
  Result<cv::Mat> gray = ToGray(data, size, arv_buffer_get_image_width(buffer),
                                arv_buffer_get_image_height(buffer), pixel_format_);
  if (!gray.ok()) {
    ++stats_.dropped;
    stats_.last_drop = gray.status().message();
    return std::nullopt;
  }
  CapturedFrame frame;
  frame.image = std::move(gray).value();
  frame.arrival_t = static_cast<double>(arv_buffer_get_system_timestamp(buffer)) * 1e-9;
  frame.t = options_.timestamps == "arrival"
                ? frame.arrival_t
                : clock_.Map(static_cast<double>(arv_buffer_get_timestamp(buffer)) * 1e-9,
                             frame.arrival_t);
  if (options_.timestamps != "arrival" && clock_.samples() < kClockSettleFrames) {
    ++stats_.clock_settling;
    return std::nullopt;
  }
  ++stats_.frames;
  return frame;
}

CameraStats AravisCamera::stats() const {
  CameraStats s = stats_;
  if (stream_ != nullptr && ARV_IS_GV_STREAM(stream_)) {
    guint64 resent = 0, missing = 0;
    arv_gv_stream_get_statistics(ARV_GV_STREAM(stream_), &resent, &missing);
    s.resent_packets = static_cast<long long>(resent);
    s.lost_packets = static_cast<long long>(missing);
  }
  return s;
}

}  // namespace fleetloc::camera_io
