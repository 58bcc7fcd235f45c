#include "colmap_ext/synthetic/rendered_project.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "colmap_ext/io/png.h"
#include "madsfm/io/depth_map_io.h"
#include "madsfm/io/json_writer.h"

namespace madsfm::colmap {

RenderedProjectSummary WriteRenderedProject(const MultiViewSceneOptions& options, uint64_t seed,
                                            const std::string& output_path) {
  const auto start = std::chrono::steady_clock::now();
  const MultiViewScene renderer(options, seed);

  namespace fs = std::filesystem;
  const fs::path root(output_path);
  fs::create_directories(root / "images");
  fs::create_directories(root / "depths");
  fs::create_directories(root / "true_depths");
  nlohmann::json images = nlohmann::json::array();
  for (int i = 0; i < renderer.NumImages(); ++i) {
    const MultiViewImage image = renderer.Render(i);
    const MultiViewCamera& cam = image.camera;
    WritePng((root / "images" / image.name).string(), cam.width, cam.height, 3, image.rgb.data());
    WriteDepthMapNpy(image.prior, (root / "depths" / (image.name + ".npy")).string());
    WriteDepthMapNpy(image.depth, (root / "true_depths" / (image.name + ".npy")).string());
    nlohmann::json entry;
    entry["name"] = image.name;
    entry["R"] = nlohmann::json::array();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) entry["R"].push_back(cam.R(r, c));
    }
    entry["t"] = {cam.t.x(), cam.t.y(), cam.t.z()};
    entry["f"] = cam.focal;
    entry["cx"] = cam.cx;
    entry["cy"] = cam.cy;
    entry["width"] = cam.width;
    entry["height"] = cam.height;
    entry["prior_scale"] = image.prior_scale;
    entry["prior_shift"] = image.prior_shift;
    entry["median_depth"] = image.median_depth;
    images.push_back(entry);
  }
  nlohmann::json gt;
  gt["scene"] = MultiViewSceneTypeName(options.scene);
  gt["seed"] = seed;
  gt["motion"] = MultiViewMotionName(options.motion);
  gt["pose_convention"] = "world -> camera: x_cam = R x_world + t; camera x right, y down, z forward; metres";
  gt["pixel_convention"] = "COLMAP: upper-left pixel centre at (0.5, 0.5); principal point (cx, cy)";
  gt["prior_convention"] =
      "depths/<name>.npy holds d with z' = prior_scale * d + prior_shift, z' = true z-depth "
      "times a smooth distortion of a few percent";
  gt["images"] = images;
  const std::string gt_path = (root / "ground_truth.json").string();
  std::ofstream gt_file(gt_path);
  if (!gt_file) throw std::runtime_error("cannot write '" + gt_path + "'");
  gt_file << madsfm::DumpJson(gt, 2) << "\n";
  if (!gt_file) throw std::runtime_error("cannot write '" + gt_path + "'");
  RenderedProjectSummary summary;
  summary.num_images = renderer.NumImages();
  summary.scene = gt["scene"].get<std::string>();
  summary.focal = renderer.Focal();
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace madsfm::colmap
