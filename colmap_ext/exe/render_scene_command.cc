#include "colmap_ext/exe/render_scene_command.h"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "colmap_ext/exe/option_parser.h"
#include "colmap_ext/synthetic/rendered_project.h"
#include "madsfm/synthetic/multiview_scene.h"

namespace madsfm {

int RunRenderScene(int argc, char** argv) {
  std::string output_path, scene = "room", motion = "arc";
  double baseline_fraction = 0.08, per_image_fov_min = 0.0, per_image_fov_max = 0.0;
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
  parser.AddDefault("motion", &motion,
                    "Camera motion (room): arc (60 deg around the target), sideways (a straight walk across the view\n"
                    "of baseline_fraction x the distance), handheld (centres in a ball of that diameter), forward (a\n"
                    "straight walk of that length towards the target, heading along it).");
  parser.AddDefault("baseline_fraction", &baseline_fraction,
                    "sideways / handheld / forward: path length / distance to target.");
  parser.AddDefault("per_image_fov_min", &per_image_fov_min,
                    "per_image_fov_max > 0: each image has its own focal (horizontal FOV in [min, max] deg).");
  parser.AddDefault("per_image_fov_max", &per_image_fov_max, "See per_image_fov_min.");
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
    if (motion == "arc") {
      options.motion = MultiViewMotion::kArc;
    } else if (motion == "sideways") {
      options.motion = MultiViewMotion::kSideways;
    } else if (motion == "handheld") {
      options.motion = MultiViewMotion::kHandheld;
    } else if (motion == "forward") {
      options.motion = MultiViewMotion::kForward;
    } else {
      throw std::invalid_argument("unknown --motion '" + motion + "' (arc, sideways, handheld or forward)");
    }
    options.baseline_fraction = baseline_fraction;
    options.per_image_fov_min_deg = per_image_fov_min;
    options.per_image_fov_max_deg = per_image_fov_max;
    if (seed < 0) throw std::invalid_argument("--seed must be >= 0");
    options.num_images = num_images;
    options.image_width = image_width;
    options.image_height = image_height;
    options.fov_deg = fov_deg;
    options.prior_distortion = prior_distortion;
    options.num_threads = num_threads;
    const colmap::RenderedProjectSummary r =
        colmap::WriteRenderedProject(options, static_cast<uint64_t>(seed), output_path);
    std::fprintf(stderr, "render_scene: wrote %d images of a %s scene (f = %.2f px) to %s in %.1f s\n", r.num_images,
                 r.scene.c_str(), r.focal, output_path.c_str(), r.seconds);
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm render_scene: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

}  // namespace madsfm
