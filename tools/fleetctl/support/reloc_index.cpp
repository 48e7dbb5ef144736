// A relocalization result as JSON (see reloc_index.h).
#include "support/reloc_index.h"

namespace fleetloc::fleetctl {

nlohmann::json RelocalizationJson(const relocalization::Relocalization& r) {
  nlohmann::json json{{"found", r.found},
                      {"frame_features", r.frame_features},
                      {"matches", r.matches},
                      {"candidates", r.candidates},
                      {"verified", r.verified},
                      {"ms",
                       {{"detect", r.detect_ms},
                        {"match", r.match_ms},
                        {"cluster", r.cluster_ms},
                        {"verify", r.verify_ms},
                        {"dense", r.dense_ms},
                        {"trajectory", r.trajectory_ms},
                        {"total", r.detect_ms + r.match_ms + r.cluster_ms + r.verify_ms +
                                      r.dense_ms + r.trajectory_ms}}}};
  if (r.dense) json["dense"] = {{"best", r.dense_best}, {"second", r.dense_second}};
  if (r.dense_fine) {
    json["dense_fine"] = {{"best", r.dense_fine_best},
                          {"second", r.dense_fine_second},
                          {"ms", r.dense_fine_ms},
                          {"refine_sweep", r.dense_fine_refine_sweep},
                          {"refine_sweep_stride", r.dense_fine_refine_sweep_stride},
                          {"refine_sweep_predicted_ms", r.dense_fine_refine_sweep_predicted_ms}};
  }
  if (r.twin_checked) {
    json["twin"] = {{"own", r.twin_own},
                    {"alternative", r.twin_correlation},
                    {"inliers", r.twin_inliers},
                    {"ms", r.twin_ms}};
  }
  if (r.twin_contrast.share > 0) {
    json["twin_contrast"] = {{"told_apart", r.twins_told_apart},
                             {"own", r.twin_contrast.own},
                             {"rival", r.twin_contrast.rival},
                             {"share", r.twin_contrast.share},
                             {"pixels", r.twin_contrast.pixels}};
  }
  if (r.trajectory_frames > 0) {
    json["trajectory"] = {{"frames", r.trajectory_frames},
                          {"best", r.trajectory_best},
                          {"second", r.trajectory_second},
                          {"accepted", r.from_trajectory}};
  }
  if (!r.found) {
    json["reason"] = r.reason;
    json["ambiguous"] = r.ambiguous;
    return json;
  }
  const geometry::Pose2& p = r.base_in_map.pose;
  const Eigen::Matrix3d& c = r.base_in_map.covariance;
  json["pose"] = {{"x", p.x}, {"y", p.y}, {"theta", p.theta}};
  json["covariance"] = {c(0, 0), c(0, 1), c(0, 2), c(1, 1), c(1, 2), c(2, 2)};
  json["templates"] = r.templates;
  json["inliers"] = r.inliers;
  json["candidate_inliers"] = r.candidate_inliers;
  return json;
}

}  // namespace fleetloc::fleetctl
