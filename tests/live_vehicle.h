// A simulated vehicle driving live on the host clock, for the live-camera agent tests: its drive
// planned over a real floor (the simulator `--sim-floor` uses) with frame times on a grid of the
// frame period (where Aravis's fake camera fires), its frames rendered ahead, its wheel odometry
// published as ROS 2 nav_msgs/Odometry over DDS at its own times, and a fake GigE Vision camera
// (Aravis's ArvGvFakeCamera on 127.0.0.1) that serves the frame of the moment over GVCP/GVSP,
// stamped by a device clock that counts from the camera's power-up.
#pragma once

#include <arv.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <thread>

#include "camera_io/camera_source.h"
#include "mosaic/raster_source.h"
#include "sim/run_simulator.h"
#include "tracker_agent/ros_bridge.h"

namespace fleetloc::testing {

inline void SleepUntilHost(double t) {
  const double wait = t - camera_io::HostNow();
  if (wait > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
}

class PlannedDrive {
 public:
  // Odometry from `start_t` (on the frame-period grid), frames from start_t + frame_delay_s.
  PlannedDrive(const cv::Mat& floor, double resolution_m, int frames, double rate_hz, double start_t,
               double frame_delay_s, double speed_px_s, uint64_t seed)
      : floor_(floor, {0.0, floor.rows * resolution_m, resolution_m}), rate_hz_(rate_hz) {
    camera_.model = sim::DefaultSimCameraModel(640, 480, resolution_m);
    sim::SimOptions o;
    o.timing.frames = frames;
    o.timing.frame_rate_hz = rate_hz;
    o.timing.start_time_s = start_t;
    o.timing.frame_delay_s = frame_delay_s;
    o.timing.frame_jitter_s = 0.0;
    o.route.speed_px_s = speed_px_s;
    o.render.supersample = 2;
    o.seed = seed;
    auto sim = sim::RunSimulator::Create(&floor_, camera_.model, o);
    EXPECT_TRUE(sim.ok()) << sim.status().message();
    sim_ = std::move(sim).value();
    for (int i = 0; i < sim_->frame_count(); ++i) images_.push_back(sim_->RenderFrame(i).image);
  }
  const io::CameraFile& camera() const { return camera_; }
  sim::RunSimulator& sim() { return *sim_; }
  double first_frame_t() const { return sim_->truth().front().t; }
  double last_frame_t() const { return sim_->truth().back().t; }
  // The planned frame nearest to host time t (clamped to the drive).
  int FrameAt(double t) const {
    const long i = std::lround((t - first_frame_t()) * rate_hz_);
    return static_cast<int>(std::clamp<long>(i, 0, static_cast<long>(images_.size()) - 1));
  }
  const cv::Mat& image(int i) const { return images_[i]; }
  double frame_t(int i) const { return sim_->truth()[i].t; }

 private:
  mosaic::ImageRasterSource floor_;
  double rate_hz_;
  io::CameraFile camera_;
  std::unique_ptr<sim::RunSimulator> sim_;
  std::vector<cv::Mat> images_;
};

// Publishes the drive's odometry (base_link in odom) on rt/odom at each sample's own host time,
// stamped with it, from a thread; `mangle` may change a sample before it goes (bad input tests).
class OdometryPublisher {
 public:
  using Mangle = std::function<bool(size_t index, nav_msgs_msg_dds__Odometry_* message)>;  // false: skip
  // `min_gap_s`: at least this long between two writes (samples stamped in the past go out
  // at this pace instead of in one burst).
  OdometryPublisher(const transport::Participant& p, const std::vector<geometry::StampedPose>& samples,
                    Mangle mangle = nullptr, double min_gap_s = 0.0)
      : samples_(samples), mangle_(std::move(mangle)), min_gap_s_(min_gap_s) {
    auto topic = transport::Topic<nav_msgs_msg_dds__Odometry_>::Create(p, "rt/odom");
    EXPECT_TRUE(topic.ok());
    topic_ = std::make_unique<transport::Topic<nav_msgs_msg_dds__Odometry_>>(std::move(topic).value());
    auto writer = transport::Writer<nav_msgs_msg_dds__Odometry_>::Create(p.get(), *topic_, tracker_agent::RosDefaultQos());
    EXPECT_TRUE(writer.ok());
    writer_ = std::make_unique<transport::Writer<nav_msgs_msg_dds__Odometry_>>(std::move(writer).value());
    thread_ = std::thread([this] { Run(); });
  }
  ~OdometryPublisher() {
    stop_ = true;
    thread_.join();
  }
  bool done() const { return done_; }

 private:
  void Run() {
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
  std::vector<geometry::StampedPose> samples_;
  Mangle mangle_;
  double min_gap_s_;
  std::unique_ptr<transport::Topic<nav_msgs_msg_dds__Odometry_>> topic_;
  std::unique_ptr<transport::Writer<nav_msgs_msg_dds__Odometry_>> writer_;
  std::atomic<bool> stop_{false}, done_{false};
  std::thread thread_;
};

// Aravis's fake GigE Vision camera on 127.0.0.1 (GVCP port 3956: one at a time per host), each
// buffer filled with the drive's frame of the moment and stamped on a device clock
// `device_epoch` seconds behind the host's Unix time. `gvsp_lost_ratio`: share of GVSP packets
// it drops (Aravis asks for them again; some frames stay incomplete).
class FakeGigECamera {
 public:
  FakeGigECamera(const PlannedDrive* drive, double device_epoch, double gvsp_lost_ratio = 0.0)
      : drive_(drive), device_epoch_(device_epoch) {
    camera_ = arv_gv_fake_camera_new("127.0.0.1", "FL20");
    if (gvsp_lost_ratio > 0) g_object_set(camera_, "gvsp-lost-ratio", gvsp_lost_ratio, nullptr);
    arv_fake_camera_set_fill_pattern(arv_gv_fake_camera_get_fake_camera(camera_), &FakeGigECamera::Fill, this);
    EXPECT_TRUE(arv_gv_fake_camera_is_running(camera_));
  }
  ~FakeGigECamera() { g_object_unref(camera_); }
  long long filled() const { return filled_; }

 private:
  static void Fill(ArvBuffer* buffer, void* self_ptr, guint32, guint32, ArvPixelFormat) {
    auto* self = static_cast<FakeGigECamera*>(self_ptr);
    const double now = static_cast<double>(arv_buffer_get_timestamp(buffer)) * 1e-9;  // fill time
    const int i = self->drive_->FrameAt(now);
    const cv::Mat& image = self->drive_->image(i);
    // The buffer holds the payload (its received size is set after the fill: 0 here).
    void* data = const_cast<void*>(arv_buffer_get_data(buffer, nullptr));
    const int w = arv_buffer_get_image_width(buffer), h = arv_buffer_get_image_height(buffer);
    if (w != image.cols || h != image.rows) return;  // the agent sees a frame of the wrong size
    std::memcpy(data, image.data, image.total());
    // Within the drive the frame shows planned frame i: captured then, however late the fill
    // (the camera's own clock would say so); before and after it, the frame of the moment.
    const bool driving = now > self->drive_->first_frame_t() - 0.05 && now < self->drive_->last_frame_t() + 0.05;
    const double captured = driving ? self->drive_->frame_t(i) : now;
    arv_buffer_set_timestamp(buffer, static_cast<guint64>(std::llround((captured - self->device_epoch_) * 1e9)));
    ++self->filled_;
  }
  const PlannedDrive* drive_;
  double device_epoch_;
  ArvGvFakeCamera* camera_ = nullptr;
  std::atomic<long long> filled_{0};
};

}  // namespace fleetloc::testing
