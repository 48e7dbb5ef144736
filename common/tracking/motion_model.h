// Covariance propagation with odometry (paper 000 §2.2.3, docs/architecture.md step 1): the
// prediction is the tracker's own last estimate plus the odometry increment, and its uncertainty
// grows with the distance driven, the angle turned and the time elapsed.
#pragma once

#include "geometry/pose2.h"
#include "tracking/tracker_options.h"

namespace fleetloc::tracking {

// Covariance of an odometry increment (expressed in the frame of its start pose).
Eigen::Matrix3d IncrementCovariance(const geometry::Pose2& increment, double dt_s,
                                    const OdometryNoiseOptions& noise);

// Covariance (x, y, theta in the pose's own frame) of odometry extrapolated `span_s` past its
// newest sample under constant velocity: an unmodelled acceleration moves the pose by ½·a·span²
// (noise.extrapolation_*), and the heading error moves a point `lever_m` from the odometry frame's
// origin by that much more. Zero for span_s ≤ 0.
Eigen::Matrix3d ExtrapolationCovariance(double span_s, double lever_m,
                                        const OdometryNoiseOptions& noise);

// internal ⊕ increment with first-order covariance propagation.
geometry::PoseWithCovariance Predict(const geometry::PoseWithCovariance& internal,
                                     const geometry::Pose2& increment, double dt_s,
                                     const OdometryNoiseOptions& noise);

// The camera's own increment between two odometry poses of base_link, mount⁻¹ ⊕ (odom_from⁻¹ ⊕
// odom_to) ⊕ mount (the mount is camera_ground in base_link), with the covariance of that
// increment driven over dt_s.
geometry::PoseWithCovariance CameraIncrement(const geometry::Pose2& odom_from,
                                             const geometry::Pose2& odom_to, double dt_s,
                                             const geometry::Pose2& mount,
                                             const OdometryNoiseOptions& noise);

}  // namespace fleetloc::tracking
