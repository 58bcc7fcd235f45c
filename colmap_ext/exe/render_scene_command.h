// `madsfm render_scene`: renders a synthetic multi-view scene (src/madsfm/synthetic/multiview_scene.h) as a COLMAP
// project for the end-to-end demo.
//
// In: --output_path DIR (required), --num_images N (default 10), --seed S (default 0), --scene room|street
// (default room), --image_width/--image_height (640 x 480), --fov_deg (0 = drawn in [60, 70] from the seed),
// --prior_distortion (0.03), --motion arc|sideways|handheld|forward with --baseline_fraction (0.08),
// --per_image_fov_min / --per_image_fov_max (0: one shared focal). Parses the options and calls
// colmap::WriteRenderedProject (colmap_ext/synthetic/rendered_project.h). Out, under DIR:
//   images/img_000.png ...             the RGB images (8-bit PNG)
//   depths/img_000.png.npy ...         the monocular-depth-like priors (float32, half resolution; the sidecar
//                                      name convention <image name>.npy of docs/design.md section 5)
//   true_depths/img_000.png.npy ...    the exact z-depths at full resolution (float32, 0 = sky)
//   ground_truth.json                  {"images": [{"name", "R" (9, row-major), "t" (3), "f", "cx", "cy", "width",
//                                      "height", "prior_scale", "prior_shift"}, ...], plus scene metadata}; poses
//                                      are world -> camera (x_cam = R x_world + t), pixels in COLMAP's convention
//                                      (upper-left pixel centre at (0.5, 0.5)), prior d relates to the distorted
//                                      depth by z' = prior_scale * d + prior_shift.
// Returns EXIT_SUCCESS or EXIT_FAILURE (message on stderr).
#pragma once

namespace madsfm {

int RunRenderScene(int argc, char** argv);

}  // namespace madsfm
