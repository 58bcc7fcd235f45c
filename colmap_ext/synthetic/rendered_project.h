// Rendered COLMAP projects (`madsfm render_scene`, colmap_ext/exe/render_scene_command.h): renders a
// src/madsfm/synthetic/multiview_scene and writes, under output_path,
//   images/img_000.png ...             the RGB images (8-bit PNG)
//   depths/img_000.png.npy ...         the monocular-depth-like priors (float32, prior resolution; the sidecar name
//                                      convention <image name>.npy)
//   true_depths/img_000.png.npy ...    the exact z-depths at full resolution (float32, 0 = sky)
//   ground_truth.json                  {"images": [{"name", "R" (9, row-major), "t" (3), "f", "cx", "cy", "width",
//                                      "height", "prior_scale", "prior_shift", "median_depth"}, ...], plus scene,
//                                      seed, motion and the conventions}; poses are world -> camera.
#pragma once

#include <cstdint>
#include <string>

#include "madsfm/synthetic/multiview_scene.h"

namespace madsfm::colmap {

struct RenderedProjectSummary {
  int num_images = 0;
  std::string scene;   // "room", "street"
  double focal = 0.0;  // the shared focal (per-image focals: ground_truth.json)
  double seconds = 0.0;
};

// Throws std::invalid_argument on bad options (MultiViewSceneOptions::Check) and std::runtime_error naming the file
// it cannot write.
RenderedProjectSummary WriteRenderedProject(const MultiViewSceneOptions& options, uint64_t seed,
                                            const std::string& output_path);

}  // namespace madsfm::colmap
