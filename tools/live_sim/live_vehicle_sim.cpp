// The live simulated vehicle: planned drive, odometry over DDS, the fake GigE Vision camera.
#include "live_sim/live_vehicle_sim.h"

#include <arv.h>

#include <chrono>
#include <cmath>
#include <cstring>

#include "camera_io/camera_source.h"
#include "tracker_agent/ros_bridge.h"
#include "transport/ros_messages.h"

namespace fleetloc::live_sim {

void SleepUntilHost(double t) {
  const double wait = t - camera_io::HostNow();
  if (wait > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
}

Result<std::unique_ptr<PlannedDrive>> PlannedDrive::Create(const cv::Mat& floor,
                                                           double resolution_m, int frames,
                                                           double rate_hz, double start_t,
                                                           double lead_s, double speed_px_s,
                                                           uint64_t seed) {
  std::unique_ptr<PlannedDrive> d(new PlannedDrive(floor, resolution_m, rate_hz));
  d->camera_.model = sim::DefaultSimCameraModel(640, 480, resolution_m);
  sim::SimOptions o;
  o.timing.frames = frames;
  o.timing.frame_rate_hz = rate_hz;
  o.timing.start_time_s = start_t + lead_s;
  o.timing.frame_delay_s = 0.0;
  o.timing.frame_jitter_s = 0.0;  // on the camera's grid
  o.route.speed_px_s = speed_px_s;
  o.render.supersample = 2;
  o.seed = seed;
  auto sim = sim::RunSimulator::Create(&d->floor_, d->camera_.model, o);
  if (!sim.ok()) return sim.status();
  d->sim_ = std::move(sim).value();
  for (int i = 0; i < d->sim_->frame_count(); ++i)
    d->images_.push_back(d->sim_->RenderFrame(i).image);
  const std::vector<geometry::StampedPose>& wheels = d->sim_->odometry();
  for (double t = start_t; t < wheels.front().t - 0.005; t += 0.01)
    d->odometry_.push_back({t, wheels.front().pose});
  d->odometry_.insert(d->odometry_.end(), wheels.begin(), wheels.end());
  return d;
}

int PlannedDrive::FrameAt(double t) const {
  const long i = std::lround((t - first_frame_t()) * rate_hz_);
  return static_cast<int>(std::clamp<long>(i, 0, static_cast<long>(images_.size()) - 1));
}

std::optional<int> PlannedDrive::FrameCapturedBy(double t) const {
  // The camera fires at or just after a grid time (microseconds): a thousandth of a period's
  // allowance (0.1 ms at 10 Hz) for the rounding of both clocks.
  const double periods = (t - first_frame_t()) * rate_hz_ + 1e-3;
  if (periods < 0 || periods >= static_cast<double>(images_.size())) return std::nullopt;
  return static_cast<int>(std::floor(periods));
}

Result<std::unique_ptr<OdometryPublisher>> OdometryPublisher::Create(
    const transport::Participant& p, std::vector<geometry::StampedPose> samples, Mangle mangle,
    double min_gap_s, const std::string& topic) {
  std::unique_ptr<OdometryPublisher> o(new OdometryPublisher());
  o->samples_ = std::move(samples);
  o->mangle_ = std::move(mangle);
  o->min_gap_s_ = min_gap_s;
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(transport::Topic<nav_msgs_msg_dds__Odometry_>::Create(p, topic), &o->topic_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(transport::Writer<nav_msgs_msg_dds__Odometry_>::Create(
                                        p.get(), *o->topic_, tracker_agent::RosDefaultQos()),
                                    &o->writer_));
  o->thread_ = std::thread([raw = o.get()] { raw->Run(); });
  return o;
}

OdometryPublisher::~OdometryPublisher() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void OdometryPublisher::Run() {
  static char odom[] = "odom", base[] = "base_link";
  for (size_t i = 0; i < samples_.size() && !stop_; ++i) {
    SleepUntilHost(samples_[i].t);
    if (min_gap_s_ > 0) std::this_thread::sleep_for(std::chrono::duration<double>(min_gap_s_));
    nav_msgs_msg_dds__Odometry_ m{};
    m.header.stamp = transport::ToRosTime(samples_[i].t);
    m.header.frame_id = odom;
    m.child_frame_id = base;
    m.pose.pose.position = {samples_[i].pose.x, samples_[i].pose.y, 0.0};
    m.pose.pose.orientation = transport::QuaternionOfYaw(samples_[i].pose.theta);
    if (mangle_ && !mangle_(i, &m)) continue;
    (void)writer_->Write(m);
  }
  done_ = true;
}

FakeGigECamera::FakeGigECamera(const PlannedDrive* drive, double device_epoch,
                               double gvsp_lost_ratio)
    : drive_(drive), device_epoch_(device_epoch) {
  camera_ = arv_gv_fake_camera_new("127.0.0.1", "FL20");
  if (gvsp_lost_ratio > 0) g_object_set(camera_, "gvsp-lost-ratio", gvsp_lost_ratio, nullptr);
  arv_fake_camera_set_fill_pattern(
      arv_gv_fake_camera_get_fake_camera(camera_),
      reinterpret_cast<ArvFakeCameraFillPattern>(&FakeGigECamera::Fill), this);
}

FakeGigECamera::~FakeGigECamera() { g_object_unref(camera_); }

bool FakeGigECamera::running() const { return arv_gv_fake_camera_is_running(camera_); }

void FakeGigECamera::Fill(ArvBuffer* buffer, void* self_ptr, unsigned, unsigned, unsigned) {
  auto* self = static_cast<FakeGigECamera*>(self_ptr);
  const double now = static_cast<double>(arv_buffer_get_timestamp(buffer)) * 1e-9;  // fill time
  // A frame is exposed before it is read out and sent: a fill that comes late (a loaded machine)
  // still shows, and is stamped with, the last frame due by now, never the next one (a capture
  // stamped after its own arrival would move the agent's clock mapping early).
  const std::optional<int> captured_frame = self->drive_->FrameCapturedBy(now);
  const int i = captured_frame.value_or(self->drive_->FrameAt(now));
  const cv::Mat& image = self->drive_->image(i);
  // The buffer holds the payload (its received size is set after the fill: 0 here).
  void* data = const_cast<void*>(arv_buffer_get_data(buffer, nullptr));
  const int w = arv_buffer_get_image_width(buffer), h = arv_buffer_get_image_height(buffer);
  if (w != image.cols || h != image.rows) return;  // the agent sees a frame of the wrong size
  std::memcpy(data, image.data, image.total());
  // Within the drive the frame shows planned frame i: captured then, however late the fill
  // (the camera's own clock would say so); before and after it, the frame of the moment.
  const double captured = captured_frame ? self->drive_->frame_t(i) : now;
  arv_buffer_set_timestamp(
      buffer, static_cast<guint64>(std::llround((captured - self->device_epoch_) * 1e9)));
  ++self->filled_;
}

}  // namespace fleetloc::live_sim
