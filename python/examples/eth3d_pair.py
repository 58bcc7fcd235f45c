import json
import numpy as np
import madsfm

d = "tests/data/example_pairs/1_eth3d"  # the repository's copy of ../shared/data/example_pairs/1_eth3d
info = json.load(open(f"{d}/info.json"))
kpts0, kpts1 = np.load(f"{d}/lightglue_matches_0.npy"), np.load(f"{d}/lightglue_matches_1.npy")
depth0, depth1 = madsfm.read_depth(f"{d}/da-met_depth_0.npy"), madsfm.read_depth(f"{d}/da-met_depth_1.npy")
K0, K1, T = np.array(info["K0"]), np.array(info["K1"]), np.array(info["T_0to1"])
size = (720, 480)  # of image0.png and image1.png: the depth maps are sampled at the keypoints

r = madsfm.estimate_relative_pose(kpts0, kpts1, depth0, depth1, K0, K1, image_size0=size, image_size1=size)
print(f"scale {r.scale:.4f}, shifts {r.shift0:.4f} {r.shift1:.4f}, {r.inliers_sampson.sum()}/{len(kpts0)} inliers")
print(f"errors: rotation {madsfm.rotation_error_deg(r.R, T[:3, :3]):.3f} deg, "
      f"translation {madsfm.translation_error_deg(r.t, T[:3, 3]):.3f} deg")
f = madsfm.estimate_shared_focal_relative_pose(kpts0, kpts1, depth0, depth1, K0, K1, image_size0=size,
                                               image_size1=size)
print(f"shared focal {f.f0:.1f} px (K0: {K0[0, 0]:.1f}, K1: {K1[0, 0]:.1f})")
