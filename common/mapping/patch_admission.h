// Whether a vehicle's floor patch may change the shared mosaic, decided on the map server's own
// evidence only: the server registers the patch against the current mosaic itself (its own search
// window, whatever the sender claims), then checks that enough of the patch agrees with the mosaic
// at the registered pose (ZNCC anchor blocks), that the photometry fits, that the pose the sender
// reported agrees with the registration, and that the change is plausible (a bounded fraction of
// the patch, texture not destroyed). The sender's covariance and quality never admit a patch;
// they only rank admitted ones (Admission::rank).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "mapping/change_detection.h"
#include "mapping/patch_registration.h"
#include "mosaic/raster_source.h"
#include "tracking/tracker_options.h"

namespace fleetloc::mapping {

struct AdmissionOptions {
  // The registration's prior (its search window): the sender's position sigma clamped to
  // [min, max] pixels and its heading sigma to [min, max] radians. A claimed zero covariance
  // cannot shrink the search to nothing, nor a huge one widen it without bound.
  double min_search_sigma_px = 4.0;
  double max_search_sigma_px = 20.0;
  double min_search_sigma_rad = 0.5 * 3.14159265358979 / 180;
  double max_search_sigma_rad = 3.0 * 3.14159265358979 / 180;
  // Registration quality: correspondences kept and their RMS residual.
  int min_inliers = 6;
  double max_rms_residual_px = 1.0;
  // The reported pose must agree with the registration within max(k × its claimed sigma, floor).
  double max_disagreement_sigmas = 3.0;
  double min_disagreement_px = 3.0;
  double min_disagreement_rad = 1.0 * 3.14159265358979 / 180;
  // Evidence blocks (change_detection.h): a textured block at or above anchor_ncc agrees with the
  // mosaic; below ChangeOptions::min_block_ncc it shows changed floor.
  ChangeOptions blocks{32, 0.3, 10.0, 8};
  double anchor_ncc = 0.6;
  int min_anchor_blocks = 6;
  double min_anchor_fraction = 0.3;  // of the textured, mapped blocks
  // Photometry: mosaic ≈ gain · patch + bias (PhotometricFit), and what is left of the anchor
  // blocks' difference after it (RMS, grey levels).
  double min_gain = 0.4, max_gain = 2.5;
  double max_abs_bias = 96.0;
  double max_photometric_rms = 30.0;
  // Plausible change: at most this fraction of the textured, mapped blocks changed, and at most
  // max_flattened_fraction of them were flattened — changed blocks where the patch keeps less
  // than min_texture_ratio of the mosaic's local texture (mean local standard deviation over
  // texture_window_px). A painted line flattens a narrow band (allowed); a patch that wipes the
  // texture off a large part of the floor would leave trackers nothing to lock on (refused).
  double max_changed_fraction = 0.6;
  double min_texture_ratio = 0.35;
  double max_flattened_fraction = 0.35;
  int texture_window_px = 7;
};

// Range checks, one message naming the field.
std::string OptionsProblem(const AdmissionOptions& options);

enum class Verdict {
  kAdmitted,
  kMalformed,          // covariance not symmetric positive definite, or image unusable
  kUnregistered,       // the server could not register it (or too few inliers, large residual)
  kPoseDisagrees,      // registered, but not where the sender said it was
  kNoAnchor,           // too little of it agrees with the mosaic
  kPhotometry,         // gain, bias or photometric residual out of bounds
  kImplausibleChange,  // too much of it changed
  kTextureDestroyed,   // the change flattens too much of the floor
};
// A short stable name ("unregistered", ...) for counters, logs and reports.
const char* VerdictName(Verdict verdict);

// What the server measured (for the verdict, logs and reports).
struct AdmissionEvidence {
  bool registered = false;
  int inliers = 0;
  double rms_residual_px = 0;
  double disagreement_px = 0, disagreement_rad = 0;
  int textured_blocks = 0, anchor_blocks = 0, changed_blocks = 0;
  int flattened_blocks = 0;    // changed blocks whose texture the patch wiped out
  double anchor_ncc_mean = 0;  // mean ZNCC of the anchor blocks
  double photometric_rms = 0;
  double texture_ratio = 1;  // patch / mosaic local texture over the changed blocks (1: none)
  double anchor_fraction() const {
    return textured_blocks > 0 ? double(anchor_blocks) / textured_blocks : 0;
  }
  double changed_fraction() const {
    return textured_blocks > 0 ? double(changed_blocks) / textured_blocks : 0;
  }
  double flattened_fraction() const {
    return textured_blocks > 0 ? double(flattened_blocks) / textured_blocks : 0;
  }
};

struct Admission {
  Verdict verdict = Verdict::kUnregistered;
  std::string reason;    // one line naming the failed check and its numbers; "" if admitted
  geometry::Pose2 pose;  // registered pose (use it, not the reported one), when registered
  double gain = 1.0, bias = 0.0;
  AdmissionEvidence evidence;
  std::vector<cv::Rect> changed_blocks;  // patch pixels where the floor changed (admitted only)
  double rank = 0;  // from the sender's quality and claimed sigma: orders admitted patches
  bool admitted() const { return verdict == Verdict::kAdmitted; }
};

// The sender's ranking of a patch: quality / (1 + claimed position sigma in pixels). Only orders
// patches that were admitted on the server's evidence.
double ClaimedRank(const Patch& patch, double resolution_m);

class PatchAdmission {
 public:
  // `mosaic` (the version the patches are judged against) must outlive this object.
  PatchAdmission(mosaic::RasterSource* mosaic, AdmissionOptions options,
                 tracking::TrackerOptions tracker);

  // Judges one patch against the mosaic. Never throws; an unusable patch gets a verdict.
  Admission Evaluate(const Patch& patch);

 private:
  Eigen::Matrix3d SearchPrior(const Eigen::Matrix3d& claimed) const;
  // Fills the block evidence, photometry and verdict of a registered patch.
  void Judge(const Patch& patch, Admission* admission);

  mosaic::RasterSource* mosaic_;
  AdmissionOptions options_;
  PatchRegistrar registrar_;
};

// Mean local standard deviation (over `window_px`) of `image` inside `rect` (CV_8UC1).
double MeanLocalStdDev(const cv::Mat& image, const cv::Rect& rect, int window_px);

}  // namespace fleetloc::mapping
