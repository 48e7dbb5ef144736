// Options of the mosaic tracker, as typed data with units in the names, and their validation.
#pragma once

#include "base/status.h"

namespace fleetloc::tracking {

// Odometry noise model: the 1-sigma error of an odometry increment grows with the distance
// driven, the angle turned and the time elapsed.
struct OdometryNoiseOptions {
  double along_sigma_per_m = 0.012;      // distance scale error, metres per metre
  double lateral_sigma_per_m = 0.005;    // sideways slip, metres per metre
  double heading_sigma_per_rad = 0.012;  // turn scale error, radians per radian turned
  double heading_sigma_per_m = 0.003;    // heading error per metre driven
  double heading_sigma_per_s = 0.002;    // gyro-like drift, radians per second
  double floor_sigma_m = 1e-5;           // keeps the increment covariance positive definite
  // Odometry extrapolated past its newest sample (a live frame tracked before odometry covers
  // its time) assumes constant velocity; an acceleration up to these moves the true pose by
  // ½·a·span² from the extrapolated one (ExtrapolationCovariance).
  double extrapolation_accel_m_s2 = 2.0;
  double extrapolation_angular_accel_rad_s2 = 4.0;
};

// Dense direct alignment of the whole frame (tracking/direct_aligner.h).
struct DirectAlignOptions {
  int coarsest_side_px = 40;  // the coarsest level keeps the frame's shorter side ≥ this
  // The alignment ends at the finest pyramid level that still has this many pixels, but not
  // below min_finest_level: as accurate as full resolution, several times cheaper on large
  // frames. Level 0 is avoided by default: there the frame's lens blur and sensor noise differ
  // most from the mosaic's (measured on a plain floor at 320×240: camera RMS 0.29 px ending at
  // level 0, 0.17 px ending at level 1).
  int finest_level_pixels = 60000;
  int min_finest_level = 1;
  // Frames with at most this many pixels are refined at full resolution once validated above it
  // (measured at 320×240, tuning floors: painted pavement under dust 0.125 → 0.087 px, polished
  // concrete under the held-out marks 0.159 → 0.075 px, lock unchanged; 1–4 ms more per dense
  // frame). 640×480 and larger frames end at level 1 or coarser: there it would cost 4× as much.
  int full_resolution_below_pixels = 100000;
  // The full-resolution polish (DirectAligner::Polish): Gauss–Newton steps over every pixel before
  // the final linearization (0: one step, from the final linearization alone: measured on fast
  // 640×480 frames, 0.010 px where one iteration gives 0.0085 and two 0.0082), how far it may
  // move the fit it starts from, and the weighted correlation it must reach (right fits on the
  // stress floors at 640×480: ≥ 0.48 on fast frames, ≥ 0.32 under dust; a frame of another floor
  // 0.09).
  // A fit ending at level 1 may be off by half a level pixel, one full-resolution pixel; right
  // polishes at 320×240 under `all` correlated 0.18–0.20 where the fit was 0.2–0.8 px off
  // (session 35: painted pavement 001 camera RMS 0.163 → 0.085 px with these and no χ² agreement
  // test, MosaicTracker::Polished; no other 320×240 stress cell worse, no wrong-floor frame
  // tracking).
  int polish_iterations = 1;
  // The polish of a fit valid only once polished (DirectAlignment::needs_polish) takes more steps:
  // those fits start up to 0.8 px off (polished concrete 024 at 320×240 under `all`: with one step
  // 50 of 60 frames confirmed at camera RMS 0.171 px, with two all 60 at 0.176 px; at 640×480 a
  // second step for every polish changed no cell's RMS by more than 0.0003 px).
  int confirm_polish_iterations = 2;
  double max_polish_shift_px = 1.0;
  double min_polish_correlation = 0.10;
  // A polish still moving is not at its minimum: the step its final linearization would take next
  // must be at most this (level-0 px). From 2 px off, one step went 0.85 px and stopped 1.15 px
  // from the truth, within max_polish_shift_px; the next step it would take refuses it. 0.25
  // refused right polishes on painted pavement 001 under `all` at 320×240 (0.085 → 0.132 px).
  double max_polish_next_step_px = 0.35;
  // A polish whose first step would move no pixel more than this (level-0 px) starts at its
  // minimum (a template fit): the linearization at the start is the final one, one render of the
  // view instead of two (0: always two). Off by default: at 0.1 it saved about a third of the
  // polish on template-located frames and left the 320×240 stress cells' camera RMS within
  // +0.0008 px, but at 640×480 (polished at level 1 since session 47, from the unrefined template
  // fit) the camera RMS of `clean` cells rose up to 1.6 times the two-pass one.
  double polish_single_pass_px = 0.0;
  // The polish works at the finest pyramid level whose frame has at most this many pixels (0:
  // always level 0), and at most at polish_max_level: level 0 at 320×240; level 1 at 640×480
  // (320×240 pixels: two passes over it fit the 2 ms budget, where level 0 took 3.4 ms a frame),
  // and at 1280×1024 (640×512: coarser levels keep too little of the frame's detail).
  int polish_max_level_pixels = 80000;
  int polish_max_level = 1;
  int max_points = 12000;   // pixels used per level: the strongest gradient of each cell
  int max_iterations = 10;  // Gauss–Newton iterations per level
  // A level (and the polish) stops when its step moves no pixel more than this (level px; the
  // coarser levels 5×). 0.01 → 0.03 took 12.5 → 8.4 Gauss–Newton steps a frame on polished
  // concrete 024 at 640×480 under `all` with the camera RMS unchanged (0.0779 px); with the
  // session's other changes no 320×240 or 640×480 stress cell's lock moved, nor its RMS by more
  // than 0.002 px (docs/benchmarks.md, session 39).
  double converged_px = 0.03;
  double tukey_c = 4.685;  // Tukey biweight cut-off in robust sigmas (MAD)
  // The final refinements (the polish, and the full-resolution refinement of small frames) fit
  // the frame's contrast against the view (residuals t − gain·v) instead of taking it as 1 (see
  // kMinGain in tracking/dense_linearization.h for why noisy frames need it), and the polish
  // blurs the view to the frame's blur, estimated between 0 and max_view_blur_px (0: never) at
  // steps of view_blur_step_px (see tracking/view_blur.h). Measured at 320×240 under `all`
  // (fast and dusty): camera RMS 0.16 → 0.07 px on epoxy trak1a, 0.19 → 0.14 on painted pavement,
  // 0.11 → 0.06 on painted floor 016 (docs/benchmarks.md, "Contrast and blur in the polish"). The
  // coarse-to-fine alignment that validates a dense fit keeps gain 1: its thresholds were set on
  // it.
  bool fit_contrast = true;
  // The polish weighs each pixel by its residual precision under a noise model fitted to the
  // frame (tracking/noise_precision.h): under a short exposure's noise the low-contrast pixels,
  // mostly noise once normalized, count less. Where the residuals do not grow where contrast is
  // low (clean or dusty frames) every weight stays 1. Measured at 320×240 (every frame polished,
  // 60 cells): 21 cells' camera RMS lower by more than 2 %, 2 higher (by 0.0001 and 0.0004 px),
  // the rest within 2 %; `fast` frames 5–11 % lower on 7 of 12 floors (docs/benchmarks.md,
  // session 47).
  bool noise_model = true;
  // Above level 0 the polish normalizes the frame and the view over the mosaic's window
  // (normalize_window_px) or over this wider one (level-0 px, scaled per level alike; 0: the
  // mosaic's always), whichever gives the more precise fit (the smaller image-only position
  // sigma by DirectAlignment::comparison_sigma_px), chosen on the frames the blur is estimated on
  // and kept in between. A wider window averages the noise of noisy frames over more pixels and
  // keeps a coarse texture's broader contrast; a local one keeps occluders' and vignetting's
  // effects local. Measured at 1280×1024 (docs/benchmarks.md, session 53).
  int polish_wide_window_px = 15;
  // The wide window's fit is taken only when its position sigma is below this share of the local
  // one's: the sigma counts the noise, not the pull a wider window gives strong edges (painted
  // lines, an occluder's rim) over more pixels. Set on the tuning floors (docs/benchmarks.md,
  // session 53).
  double polish_wide_window_max_sigma_ratio = 0.93;
  // At level 0 (320×240) the mosaic's normalized tiles are smoothed for the template matching
  // (match_smoothing_sigma_px), and the polish's view comes from them. The polish also normalizes
  // the frame and the view without that smoothing, on the frames the blur is estimated on, and
  // takes that fit (and keeps it in between) when its comparison sigma is below this multiple of
  // the smoothed fit's; 0: always the smoothed. Above 1 because the smoothed fit's comparison sigma
  // is the lower one even where its error is the higher (its σ²·h⁻¹ term counts the residuals the
  // smoothing lowers; session 55: compared by the reported covariance instead, at 1.0 and 1.1
  // painted pavement 001 `all` rose 0.085 → 0.13 px, at 0.9 the clean frames' gain was lost).
  // Without the smoothing, clean and lightly occluded frames fit closer; under heavy dust and blur
  // the smoothed fit is the better one. Set on the tuning floors (docs/benchmarks.md, session 54).
  double polish_unsmoothed_max_sigma_ratio = 1.1;
  double max_view_blur_px = 2.5;
  double view_blur_step_px = 0.5;
  // The estimate costs a blur and a pass per step (≈ 2.5 ms per 320×240 frame): it is made on
  // the first polished frame and then every this many frames, and kept in between (the lens's
  // blur does not change; the motion's changes with the speed).
  int view_blur_every_frames = 10;
  // Pixels whose local contrast exceeds this multiple of the frame's median local contrast (and
  // their normalization window) are occluders the mosaic lacks and are not used.
  double occluder_contrast_ratio = 3.0;
  // Neighbouring pixel residuals are not independent (blur, normalization window): the image
  // information is divided by this factor so the covariance is honest (see direct_aligner_test).
  double correlation_factor = 4.0;
  // Exhaustive search at the finest level with at most search_level_pixels pixels (coarser while
  // the prediction's 3-sigma exceeds max_search_px there), when that 3-sigma exceeds
  // search_above_px pixels of the level. Measured on a plain dusty floor at 640×480: searching at
  // 80×60 left 16 % of the frames ambiguous, at 160×120 none.
  double search_above_px = 0.0;
  int max_search_px = 24;
  // The search window's half-size in prediction sigmas: wider than the templates' 3 because the
  // odometry model is only a model (measured on fast runs over polished concrete: true poses 20 px
  // off a prediction whose 3-sigma was ~15 px, every few frames).
  double search_sigma_multiple = 5.0;
  int search_level_pixels = 25000;
  int peak_exclusion_px = 3;  // the second peak lies outside this radius of the best
  // When the predicted heading finds no clear peak, the search is repeated at up to this many
  // headings each side, spread over the prediction's ±3 sigma (one per level pixel of turn at the
  // frame's corners).
  int max_heading_steps = 3;
  // When the predicted heading's peak is significant (min_significant_peak_z), each heading of
  // that climb is probed only within ±heading_probe_px level pixels of it, turned about it, and
  // only the heading it ends at is searched over the whole window (DirectAligner::ClimbHeadings);
  // 0: every heading over the whole window.
  int heading_probe_px = 2;
  // A predicted heading's peak below min_significant_peak_z but at least this (0: never) may be
  // the frame's place or chance: the climb probes near it all the same, then searches the whole
  // window at the heading it ends at, and goes on over whole windows unless that window's peak is
  // the probed one (DirectAligner::ClimbHeadingsFromTentativePeak). Two whole windows instead of
  // three or four where the peak was the place.
  double min_tentative_peak_z = 4.0;
  // A peak at the predicted heading that is significant (min_significant_peak_z) and distinct
  // (second peak ≤ max_distinct_peak_ratio of it) ends the search there: the alignment fits the
  // rest of the turn (docs/benchmarks.md, "Significant peaks end the heading search").
  bool significant_peak_ends_search = true;
  // A fit refused after a search whose second peak exceeds max_distinct_peak_ratio of the best
  // aligns that rival too and is judged again on the two aligned fits
  // (DirectAligner::CompareWithRival); a rival converging within rival_same_place_px of the best
  // is the same place.
  bool verify_rival_peak = true;
  double rival_same_place_px = 1.0;
  // Validation of the final fit. Always: the image pins the position (max_sigma_px) and the
  // finest level correlates at all. Then either a strong fit (a distinct coarse peak, a clear
  // coarse correlation, an innovation up to max_prior_chi2) or a weak one that the prediction
  // confirms (a less distinct peak, a weaker correlation, a small innovation). Measured on
  // low-contrast floors at 320×240 and 640×480 with 30 % occluders and on kidnapped runs: wrong
  // basins correlate ≤ 0.25 at the coarsest level with peak ratio ≥ 0.4; right ones 0.3–0.9.
  double max_sigma_px = 0.5;            // image-only 1-sigma position (level-0 px), worst direction
  double min_correlation = 0.05;        // weighted NCC at the finest level
  double min_strong_correlation = 0.3;  // weighted NCC at the coarsest level
  double max_strong_peak_ratio = 0.6;   // second-best coarse peak / best
  // Innovation (fit vs prediction, χ² with 3 dof) a strong fit may have: loose, because the
  // odometry model's covariance is itself only a model (measured: fast runs over real concrete
  // photos put right fits at χ² 20–40 every few frames; wrong ones are told by their peak).
  double max_prior_chi2 = 100.0;
  // A distinct fit (a high coarse correlation and a clear peak, far from anything a wrong basin
  // has shown) may disagree with the prediction more: fast turning runs put right fits at χ²
  // 110–140 (correlation 0.84, peak ratio ≤ 0.08) where the odometry model's covariance was too
  // small, and those frames coasted.
  double min_distinct_correlation = 0.6;
  double max_distinct_peak_ratio = 0.2;
  // A fit whose coarse search found one clear peak (second peak at most this share of it) is as
  // distinct at a strong correlation: low-contrast frames under dust and fast turns put right
  // fits at correlation 0.40–0.42, peak ratio 0.09, χ² 120–130 (stress suite, 320×240, `all`).
  double max_clear_peak_ratio = 0.12;
  // A fit whose search peak stands this many standard deviations above the rest of the search
  // surface is strong and distinct whatever its correlation: the surface's own spread is the
  // floor's and the frame's noise level, so the test adapts to both. Frames aligned to another
  // floor's mosaic (7400 such fits over every stress size and condition) reach at most 6.1; right
  // fits that the correlation rules refused, 9–27 (plain floors under dust, fast turns).
  double min_significant_peak_z = 8.0;
  double min_significant_correlation = 0.3;  // the aligned frame's weighted NCC at the finest level
  // A significant fit that correlates less, down to this, is valid only once the full-resolution
  // polish confirms it (DirectAlignment::needs_polish): the plainest floor's fits sit in the
  // right basin but up to 0.8 px off, and the polish over every pixel takes them to the truth
  // (polished concrete 024 at 320×240 under `all`: fits correlating 0.16–0.27 at z 9–16, no
  // frame locked with 0.3; with this rule every frame, camera RMS 0.18 px, none 0.5 px off).
  // Cameras whose frames are not polished (neither polish_dense_max_frame_pixels nor
  // polish_min_frame_pixels) keep refusing them; at 1280×1024 the level-1 polish confirms them.
  double min_polished_significant_correlation = 0.15;
  double max_distinct_prior_chi2 = 400.0;
  // The weak rule was 0.2 / 0.65 when tuned on proxy floors; the first holdout run of the stress
  // suite found two false locks through it (3.2 and 5.7 px off at correlation 0.28 and 0.24,
  // peak ratio 0.35 and 0.51), so it now needs a distinct peak as well.
  // A fit is strong too when the finest level correlates this well after a coarse peak that is not
  // ambiguous (second peak ≤ max_weak_peak_ratio): an upscaled plain floor has little texture left
  // at the search level (polished concrete at 1280×1024 under dust: right fits at 0.49–0.53 here,
  // 0.27–0.29 at the search level, peak ratio 0.23–0.29), while frames aligned to another floor's
  // mosaic reach at most 0.27 here at peak ratios ≥ 0.75 (1200 such fits, every size and
  // condition).
  double min_fine_strong_correlation = 0.4;
  double min_weak_correlation = 0.25;
  double max_weak_peak_ratio = 0.3;
  double max_weak_prior_chi2 = 6.0;
};

struct TrackerOptions {
  int template_size_px = 48;  // side of a square template (multiple of 4)
  // Where the standard templates fail, larger ones are tried before the dense alignment (0: never):
  // more pixels per template hold a weak floor's faint texture above the noise. Measured on the
  // stress suite's `all` condition at 640×480 (tuning floors): 64 px locks dark plain concrete
  // that 48 px cannot (5.5 → 1.6 ms per frame, camera RMS 0.046 → 0.038 px); 96 px gained no more.
  int weak_template_size_px = 64;
  int max_templates = 28;
  int min_inliers = 4;         // fewer kept matches than this → coasting
  int candidate_step_px = 16;  // grid of template candidates in the frame
  int texture_window_px = 5;   // at half resolution
  // A candidate site needs texture (the smallest eigenvalue of the structure matrix, (grey
  // levels/px)², at half resolution) of at least relative_texture × the frame's texture_quantile
  // score, and at least min_texture: relative, so a plain floor keeps its best sites.
  double min_texture = 2.0;
  double relative_texture = 0.0;
  double texture_quantile = 0.9;
  // The standard templates' candidates have their texture capped at this quantile of theirs (0:
  // no cap; CapTexture in feature_selection.h), so that debris and marks, the strongest texture
  // of an occluded frame, do not take every pick. Painted pavement 001 under `dusty` at 640×480:
  // the standard templates located 21 of 60 frames instead of 6, the cycle's instructions −8 %
  // (−5 % on plain concrete b1 and epoxy trak1a under `all`, within 2 % on clean and marked
  // floors); camera RMS of the 640×480 grid ×0.998 (geometric mean; 0.91–1.09), 1280×1024 ×1.004,
  // 320×240 unchanged (docs/benchmarks.md, session 49). The weak-floor templates keep their
  // best-textured sites.
  double texture_cap_quantile = 0.5;
  double spread_sigma_px = 120.0;  // feature selection: distance scale of the spread bonus
  int normalize_window_px = 7;
  // Gaussian smoothing of the normalized frame and mosaic at full resolution before they are
  // correlated (0: none). The frame is an area-sampled, blurred view of the floor, the mosaic its
  // sharp photograph resampled bilinearly at a varying sub-pixel phase: smoothing both alike takes
  // out the difference in their finest detail, which otherwise biases each template's sub-pixel
  // peak, but it also takes information where the frame is sharp and noisy. Camera-centre RMS
  // (px) at σ 0 / 0.7 / 1.5:
  // - stress suite, clean 640×480: fine aggregate 0.057 / 0.035 / 0.017, plain concrete
  //   0.019 / 0.013 / 0.008;
  // - stress suite, dusty plain concrete (blurred frames): 0.023 / 0.020 / 0.034;
  // - demo stone floor (`bench tracker`, 1000 frames, base_link RMS against the 0.1 px target):
  //   0.088 / 0.095 / 0.122.
  // 0.7 keeps every demo floor within its target and most of the gain on the stress floors.
  double match_smoothing_sigma_px = 0.7;
  double min_peak_correlation = 0.4;
  double max_ambiguity_ratio = 0.92;   // second peak / best peak
  double min_peak_curvature = 0.005;   // NCC per px² at the peak; flatter peaks are rejected
  double search_sigma_multiple = 3.0;  // search window half-size = this × prediction sigma
  int min_search_radius_px = 3;
  int max_search_radius_px = 48;    // beyond this the prediction is too poor: lost
  int refine_search_radius_px = 2;  // fine passes around the previous solution
  // Extra fine passes after the first: the mosaic is resampled at the refined pose and the inliers
  // matched again within ±refine radius, where the quadratic peak fit's pixel-locking bias
  // vanishes. One pass: camera RMS 0.009–0.014 → 0.003–0.005 px on the clean 640×480 stress floors
  // (below ECC's 0.005–0.009), demo floors base_link 0.051 → 0.041 px, +0.45 ms per frame.
  // Skipped on frames that are polished (polish_max_frame_pixels), which end at the same pose.
  int refine_passes = 1;
  // The extra passes' window (±px): they start at a pose good to a small fraction of a pixel, so
  // the peak is the window's centre and a 3×3 surface holds the quadratic fit's whole
  // neighbourhood (the same fit as in a 5×5 one, whose second peak lies within the centre's
  // exclusion radius anyway); a template whose peak is off the centre is matched again within
  // ±refine_search_radius_px. 7 % fewer instructions per 640×480 frame (worn asphalt b1, clean
  // and fast), the stress cells' poses unchanged (docs/benchmarks.md, session 41).
  int refine_pass_radius_px = 1;
  // Coarse-to-fine: when the search radius exceeds coarse_above_radius_px, the first search runs
  // at pyramid level coarse_levels (each level halves the resolution and the radius) on the first
  // coarse_templates sites, each finer level refines ±refine radius, and the full-resolution
  // search only covers ±refine radius.
  int coarse_above_radius_px = 4;
  int coarse_levels = 2;            // the coarsest level the search may start at
  int coarse_search_radius_px = 8;  // it starts at the finest level whose radius is ≤ this
  int coarse_templates = 12;
  int coarse_template_size_px = 48;      // level-0 pixels (halved per level)
  double measurement_sigma_px = 0.15;    // 1-sigma of one template correspondence
  double outlier_ratio = 3.0;            // reject residual > ratio × median of the rest …
  double min_outlier_residual_px = 0.6;  // … and above this
  int max_coasting_frames = 50;          // after this many frames without a fix: lost
  int normalized_cache_mb = 128;         // normalized mosaic tiles (floats) kept in memory
  // The dense alignment runs when the templates do not lock, and after they do when
  // direct_refine is set (it then gives the final pose when it agrees with the templates).
  bool direct_refine = false;
  // On cameras of at most this many pixels every located frame's fit is polished over all its
  // pixels at the polish level (DirectAligner::Polish: level 0 at 320×240, level 1 at 640×480,
  // direct.polish_max_level_pixels) and the polished fit taken when it validates and agrees (0:
  // never). At 320×240 it divides the camera RMS by 1.4–5 on every stress cell (the templates use
  // a fifth of the pixels; docs/benchmarks.md, "Full-resolution polish"). At 640×480 (since
  // session 48) it halves the camera RMS (57 of the 60 stress cells lower, none higher) and takes
  // the `fast` cells from 3 to 10 of 12 under whole-frame ECC, for about 0.6 ms a frame: the
  // textured floors' median frame 1.8–2.2 ms with polished_max_templates templates and the
  // standard templates tried first again after a failure (ChooseTemplateSizeAfter).
  // deploy/config/tracker/light_640.json (100000) keeps 640×480 unpolished, at about 1.3 ms
  // (docs/benchmarks.md, "Every 640×480 frame polished by default").
  int polish_max_frame_pixels = 307200;
  // A camera of at most polish_max_frame_pixels keeps at most this many standard templates (and
  // max_templates): polished, they need only bring the fit within the polish's reach and agree on
  // it; 10 and 14 gave the same camera RMS at 640×480 (every cell within 4 %), 28 cost 0.3 ms more
  // a frame. The weak-floor templates (weak_template_size_px) and large cameras that polish every
  // frame (polish_min_frame_pixels) keep max_templates: with 10, plain concrete b1 under `all` at
  // 640×480 locked 14 of 60 frames with the templates instead of 49, and at 1280×1024 the cap
  // raised 9 cells' camera RMS by 3–20 %.
  int polished_max_templates = 10;
  // On cameras of at least this many pixels (0: none) every located frame is polished too, at
  // level 1 (direct.polish_max_level_pixels): there the templates use a smaller share of the
  // frame's pixels, and the polish has as many pixels as a 640×480 frame's. Measured on the
  // painted floor 016 (holdout) at 1280×1024 under `all`: camera RMS 0.108 → 0.017 px, the
  // polish 9 ms a frame on a loaded host (docs/benchmarks.md, session 39).
  int polish_min_frame_pixels = 1000000;
  // On cameras of at most this many pixels that do not polish every frame (since session 47 only
  // when polish_max_frame_pixels is set below the camera's size), the frames the dense alignment
  // located with a finest-level correlation below polish_dense_below_correlation are polished: that
  // fit ends at level 1 or coarser (the templates' at full resolution), and is least precise where
  // it correlates weakly. At 640×480 under `all`: polished concrete 024 (dense fits correlating
  // 0.24–0.30) camera RMS 0.189 → 0.078 px; the textured floors' dense fits (0.34–0.51, within
  // their targets) stay unpolished, which keeps their time (docs/benchmarks.md, "The dense fits
  // polished at 640×480").
  int polish_dense_max_frame_pixels = 307200;
  double polish_dense_below_correlation = 0.33;
  // Those polishes work at the finest pyramid level whose frame has at most this many pixels (0:
  // level 0): level 1 at 640×480, the level their fit ended at, but over every pixel where the
  // fit took the 12000 strongest. At 640×480 under `all`, against level 0: polished concrete 024
  // camera RMS 0.0779 → 0.0768 px, painted pavement 001 0.0849 → 0.0847, the polish ~4× fewer
  // sums; no other 640×480 stress cell polishes, no wrong-floor frame tracks (docs/benchmarks.md,
  // session 44).
  int polish_dense_max_level_pixels = 80000;
  // After direct_first_after_failures frames in a row that the templates failed on, the last of
  // them locked by the dense alignment (a weak floor, not a one-off bad prediction), the next
  // frames start with the dense alignment; the templates are tried again after
  // retry_templates_frames frames. One failure alone does not switch: on a textured floor a
  // prediction far off its sigma fails the templates once, and ten dense frames after it cost
  // 4 ms each (measured: fast runs over epoxy, 640×480, median 1.3 → 5.5 ms). It also bounds how
  // many frames the weak-floor templates go first for (MosaicTracker::ChooseTemplateSizeAfter).
  int retry_templates_frames = 10;
  int direct_first_after_failures = 2;
  // Template and dense fits disagreeing by more than this (chi², 3 dof, on the sum of their
  // covariances) make the frame coast: one of them is wrong and nothing says which.
  double max_disagreement_chi2 = 21.1;
  OdometryNoiseOptions odometry;
  DirectAlignOptions direct;
};

// Flat lists of range checks; the message names the offending field.
Status Validate(const DirectAlignOptions& options);
Status Validate(const TrackerOptions& options);

// `options` for a tracker whose fits are judged by their template inliers (relocalization's
// verifying cycle, the map server's patch registration): their thresholds were set with
// max_templates templates, so the cap of a camera that polishes every frame
// (polished_max_templates) is lifted.
TrackerOptions CountingTemplateInliers(TrackerOptions options);

}  // namespace fleetloc::tracking
