#include "colmap_ext/exe/render_scene_command.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "colmap_ext/exe/option_parser.h"
#include "colmap_ext/io/png.h"
#include "madsfm/io/depth_map_io.h"
#include "madsfm/io/json_writer.h"
#include "madsfm/synthetic/multiview_scene.h"

namespace madsfm {

int RunRenderScene(int argc, char** argv) {
  std::string output_path, scene = "room";
  int num_images = 10, seed = 0, image_width = 640, image_height = 480, num_threads = 0;
  double fov_deg = 0.0, prior_distortion = 0.03;
  OptionParser parser("render_scene",
                      "Renders a synthetic multi-view scene (textured boxes, ray cast) as a COLMAP project:\n"
                      "<output_path>/images/*.png, depth priors <output_path>/depths/<image>.npy (unknown scale and\n"
                      "shift per image plus a smooth distortion), exact depths <output_path>/true_depths/<image>.npy\n"
                      "and the ground-truth cameras <output_path>/ground_truth.json (x_cam = R x_world + t).");
  parser.AddRequired("output_path", &output_path, "Project directory to write into (created).");
  parser.AddDefault("num_images", &num_images, "Number of images (8-15 intended).");
  parser.AddDefault("seed", &seed, "Seed of the scene, cameras, textures and priors.");
  parser.AddDefault("scene", &scene, "Scene: room or street.");
  parser.AddDefault("image_width", &image_width, "Image width in pixels.");
  parser.AddDefault("image_height", &image_height, "Image height in pixels.");
  parser.AddDefault("fov_deg", &fov_deg, "Horizontal field of view in degrees (0: drawn in [60, 70] from the seed).");
  parser.AddDefault("prior_distortion", &prior_distortion, "Magnitude of the smooth non-affine prior distortion.");
  parser.AddDefault("num_threads", &num_threads, "Rendering threads (0: all cores).");
  if (!parser.Parse(argc, argv, 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  try {
    MultiViewSceneOptions options;
    if (scene == "room") {
      options.scene = MultiViewSceneType::kRoom;
    } else if (scene == "street") {
      options.scene = MultiViewSceneType::kStreet;
    } else {
      throw std::invalid_argument("unknown --scene '" + scene + "' (room or street)");
    }
    if (seed < 0) throw std::invalid_argument("--seed must be >= 0");
    options.num_images = num_images;
    options.image_width = image_width;
    options.image_height = image_height;
    options.fov_deg = fov_deg;
    options.prior_distortion = prior_distortion;
    options.num_threads = num_threads;
    const auto start = std::chrono::steady_clock::now();
    const MultiViewScene renderer(options, static_cast<uint64_t>(seed));

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
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "render_scene: wrote %d images of a %s scene (f = %.2f px) to %s in %.1f s\n",
                 renderer.NumImages(), gt["scene"].get<std::string>().c_str(), renderer.Focal(), output_path.c_str(),
                 seconds);
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm render_scene: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

}  // namespace madsfm
