#include "madsfm/synthetic/two_view_scene.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "madsfm/synthetic/scene_primitives.h"

namespace madsfm {
namespace {

using synthetic::Box;
using synthetic::Rng;
using synthetic::SplitMix64;
using synthetic::ToLocal;
using synthetic::ToWorld;

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

double DegToRad(double deg) { return deg * kPi / 180.0; }

// ------------------------------------------------------------------------------------------------------------------
// Scene: boxes (yawed about the vertical z axis), an optional room (a box seen from inside), an optional ground plane
// z = 0 and an optional vertical background cylinder. Every planar face has its own surface id.

// Slab test in a box's frame (lo, ld: ray origin relative to the centre and direction, in box axes): entry/exit
// parameters and faces; false if the ray line misses the box.
inline bool SlabsLocal(const Eigen::Vector3d& half, const Eigen::Vector3d& lo, const Eigen::Vector3d& ld,
                       double* t_near, int* f_near, double* t_far, int* f_far) {
  double tn = -kInf, tf = kInf;
  int fn = -1, ff = -1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(ld[k]) < 1e-15) {
      if (std::abs(lo[k]) > half[k]) return false;
      continue;
    }
    const double inv = 1.0 / ld[k];
    const double ta = (-half[k] - lo[k]) * inv, tb = (half[k] - lo[k]) * inv;
    const bool forward = ta <= tb;  // the -half face is entered first
    const double t1 = forward ? ta : tb, t2 = forward ? tb : ta;
    if (t1 > tn) {
      tn = t1;
      fn = forward ? 2 * k : 2 * k + 1;
    }
    if (t2 < tf) {
      tf = t2;
      ff = forward ? 2 * k + 1 : 2 * k;
    }
  }
  if (tn > tf) return false;
  *t_near = tn;
  *f_near = fn;
  *t_far = tf;
  *f_far = ff;
  return true;
}

bool IntersectSlabs(const Box& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t_near, int* f_near,
                    double* t_far, int* f_far) {
  return SlabsLocal(b.half, ToLocal(b, o - b.center), ToLocal(b, d), t_near, f_near, t_far, f_far);
}

struct Scene {
  bool has_room = false;
  Box room;
  std::vector<Box> boxes;
  bool has_ground = false;
  int ground_surface = -1;
  bool has_background = false;
  Eigen::Vector2d background_center = Eigen::Vector2d::Zero();
  double background_radius = 0.0, background_height = 0.0;
  int background_surface = -1;
  int num_surfaces = 0;
  double sky_depth = 0.0;  // depth a "MDE model" predicts where there is no surface
  bool planar = false;     // kPlanar: an empty room, camera 0 faces wall x = 0
};

constexpr double kMinT = 1e-9;

bool IntersectRoom(const Scene& s, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t, int* surface) {
  double tn, tf;
  int fn, ff;
  if (!IntersectSlabs(s.room, o, d, &tn, &fn, &tf, &ff) || tf <= kMinT) return false;
  *t = tf;
  *surface = s.room.first_surface + ff;
  return true;
}

bool IntersectBox(const Box& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t, int* surface) {
  double tn, tf;
  int fn, ff;
  if (!IntersectSlabs(b, o, d, &tn, &fn, &tf, &ff) || tn <= kMinT) return false;
  *t = tn;
  *surface = b.first_surface + fn;
  return true;
}

bool IntersectGround(const Scene& s, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t, int* surface) {
  if (d.z() >= -1e-15 || o.z() <= 0.0) return false;
  *t = -o.z() / d.z();
  *surface = s.ground_surface;
  return *t > kMinT;
}

bool IntersectBackground(const Scene& s, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t,
                         int* surface) {
  const Eigen::Vector2d oc = o.head<2>() - s.background_center;
  const Eigen::Vector2d dxy = d.head<2>();
  const double a = dxy.squaredNorm();
  if (a < 1e-20) return false;
  const double b = 2.0 * oc.dot(dxy);
  const double c = oc.squaredNorm() - s.background_radius * s.background_radius;
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return false;
  const double tt = (-b + std::sqrt(disc)) / (2.0 * a);
  if (tt <= kMinT) return false;
  const double z = o.z() + tt * d.z();
  if (z < 0.0 || z > s.background_height) return false;
  *t = tt;
  *surface = s.background_surface;
  return true;
}

// Nearest hit along o + t d (t > 0). With d = R^T K^-1 [x y 1]^T, t is the z-depth in that camera.
bool Cast(const Scene& s, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t_hit, int* surface_hit) {
  double best = kInf;
  int best_surface = -1;
  double t;
  int surface;
  if (s.has_room && IntersectRoom(s, o, d, &t, &surface) && t < best) best = t, best_surface = surface;
  if (s.has_ground && IntersectGround(s, o, d, &t, &surface) && t < best) best = t, best_surface = surface;
  if (s.has_background && IntersectBackground(s, o, d, &t, &surface) && t < best) best = t, best_surface = surface;
  for (const Box& b : s.boxes) {
    if (IntersectBox(b, o, d, &t, &surface) && t < best) best = t, best_surface = surface;
  }
  if (best_surface < 0) return false;
  *t_hit = best;
  *surface_hit = best_surface;
  return true;
}

Box MakeBox(Scene* s, const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw) {
  return synthetic::MakeBox(center, size, yaw, &s->num_surfaces);
}

// Is p at least margin away from every solid (and inside the room / above the ground)?
bool IsFree(const Scene& s, const Eigen::Vector3d& p, double margin) {
  if (s.has_room) {
    const Eigen::Vector3d l = p - s.room.center;
    for (int k = 0; k < 3; ++k) {
      if (std::abs(l[k]) > s.room.half[k] - margin) return false;
    }
  }
  if (s.has_ground && p.z() < margin) return false;
  if (s.has_background && (p.head<2>() - s.background_center).norm() > s.background_radius - 20.0) return false;
  for (const Box& b : s.boxes) {
    const Eigen::Vector3d l = ToLocal(b, p - b.center);
    if (std::abs(l.x()) < b.half.x() + margin && std::abs(l.y()) < b.half.y() + margin &&
        std::abs(l.z()) < b.half.z() + margin)
      return false;
  }
  return true;
}

void BuildIndoorScene(Rng& rng, Scene* s) {
  const Eigen::Vector3d room_size(rng.Uniform(3.5, 8.0), rng.Uniform(3.5, 8.0), rng.Uniform(2.4, 3.2));
  s->has_room = true;
  s->room = MakeBox(s, 0.5 * room_size, room_size, 0.0);
  const int num_objects = rng.UniformInt(3, 6);
  for (int i = 0; i < num_objects; ++i) {
    const int kind = rng.UniformInt(0, 2);
    if (kind == 0) {  // crate on the floor
      const Eigen::Vector3d size(rng.Uniform(0.3, 1.0), rng.Uniform(0.3, 1.0), rng.Uniform(0.3, 1.0));
      const double r = 0.5 * size.head<2>().norm() + 0.05;
      const Eigen::Vector3d c(rng.Uniform(r, room_size.x() - r), rng.Uniform(r, room_size.y() - r), 0.5 * size.z());
      s->boxes.push_back(MakeBox(s, c, size, rng.Uniform(0.0, kPi)));
    } else if (kind == 1) {  // table: a top and four legs
      const double tx = rng.Uniform(0.8, 1.6), ty = rng.Uniform(0.6, 1.0), h = rng.Uniform(0.7, 0.8);
      const double yaw = rng.Uniform(0.0, kPi);
      const double r = 0.5 * std::hypot(tx, ty) + 0.05;
      const Eigen::Vector3d c(rng.Uniform(r, room_size.x() - r), rng.Uniform(r, room_size.y() - r), h - 0.02);
      const Box top = MakeBox(s, c, Eigen::Vector3d(tx, ty, 0.04), yaw);
      s->boxes.push_back(top);
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d local((k & 1 ? 1 : -1) * (0.5 * tx - 0.06), (k & 2 ? 1 : -1) * (0.5 * ty - 0.06), 0.0);
        Eigen::Vector3d leg_center = c + ToWorld(top, local);
        leg_center.z() = 0.5 * (h - 0.04);
        s->boxes.push_back(MakeBox(s, leg_center, Eigen::Vector3d(0.05, 0.05, h - 0.04), yaw));
      }
    } else {  // cabinet against a wall
      const int wall = rng.UniformInt(0, 3);
      const double width = rng.Uniform(0.8, 2.0), depth = rng.Uniform(0.35, 0.6), height = rng.Uniform(0.9, 2.1);
      const bool along_x = wall >= 2;  // walls 2, 3 are y = 0 and y = Wy: the cabinet runs along x
      const double len = along_x ? room_size.x() : room_size.y();
      const double w = std::min(width, len - 0.2);
      const double pos = rng.Uniform(0.5 * w + 0.05, len - 0.5 * w - 0.05);
      const double off = 0.5 * depth + 0.01;
      Eigen::Vector3d c;
      if (wall == 0) c = Eigen::Vector3d(off, pos, 0.5 * height);
      if (wall == 1) c = Eigen::Vector3d(room_size.x() - off, pos, 0.5 * height);
      if (wall == 2) c = Eigen::Vector3d(pos, off, 0.5 * height);
      if (wall == 3) c = Eigen::Vector3d(pos, room_size.y() - off, 0.5 * height);
      const Eigen::Vector3d size = along_x ? Eigen::Vector3d(w, depth, height) : Eigen::Vector3d(depth, w, height);
      s->boxes.push_back(MakeBox(s, c, size, 0.0));
    }
  }
  s->sky_depth = 2.0 * room_size.norm();  // never seen from inside the room
}

void BuildPlanarScene(Rng& rng, Scene* s) {
  const Eigen::Vector3d room_size(rng.Uniform(10.0, 20.0), rng.Uniform(10.0, 20.0), rng.Uniform(3.0, 4.0));
  s->has_room = true;
  s->room = MakeBox(s, 0.5 * room_size, room_size, 0.0);
  s->planar = true;
  s->sky_depth = 2.0 * room_size.norm();
}

void BuildOutdoorScene(Rng& rng, Scene* s) {
  s->has_ground = true;
  s->ground_surface = s->num_surfaces++;
  s->has_background = true;
  s->background_center = Eigen::Vector2d::Zero();
  s->background_radius = rng.Uniform(150.0, 200.0);
  s->background_height = rng.Uniform(15.0, 45.0);
  s->background_surface = s->num_surfaces++;
  const int num_buildings = rng.UniformInt(6, 12);
  for (int i = 0; i < num_buildings; ++i) {
    const Eigen::Vector3d size(rng.Uniform(8.0, 30.0), rng.Uniform(8.0, 20.0), rng.Uniform(6.0, 35.0));
    const double min_r = 0.5 * size.head<2>().norm() + 8.0;
    const double r = std::max(min_r, rng.Uniform(15.0, 100.0));
    const double angle = rng.Uniform(0.0, 2.0 * kPi);
    s->boxes.push_back(MakeBox(s, Eigen::Vector3d(r * std::cos(angle), r * std::sin(angle), 0.5 * size.z()), size,
                               rng.Uniform(0.0, kPi)));
  }
  const int num_small = rng.UniformInt(3, 8);
  for (int i = 0; i < num_small; ++i) {
    const Eigen::Vector3d size(rng.Uniform(1.5, 4.5), rng.Uniform(1.5, 2.0), rng.Uniform(1.2, 2.5));
    const double min_r = 0.5 * size.head<2>().norm() + 4.0;
    const double r = std::max(min_r, rng.Uniform(4.0, 30.0));
    const double angle = rng.Uniform(0.0, 2.0 * kPi);
    s->boxes.push_back(MakeBox(s, Eigen::Vector3d(r * std::cos(angle), r * std::sin(angle), 0.5 * size.z()), size,
                               rng.Uniform(0.0, kPi)));
  }
  s->sky_depth = 2.0 * s->background_radius;
}

// ------------------------------------------------------------------------------------------------------------------
// Cameras.

struct Camera {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d K_inv = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // cam_from_world rotation
  Eigen::Vector3d C = Eigen::Vector3d::Zero();      // centre in the world
  int width = 0, height = 0;

  // World direction of the ray through pixel (x, y), scaled so that the ray parameter is the z-depth.
  Eigen::Vector3d Ray(double x, double y) const { return R.transpose() * (K_inv * Eigen::Vector3d(x, y, 1.0)); }
  // Projects a world point; false if it is not in front of the camera.
  bool Project(const Eigen::Vector3d& X, Eigen::Vector2d* p, double* z) const {
    const Eigen::Vector3d Xc = R * (X - C);
    if (Xc.z() <= 1e-9) return false;
    const Eigen::Vector3d h = K * Xc;
    *p = h.head<2>() / h.z();
    *z = Xc.z();
    return true;
  }
  bool InImage(const Eigen::Vector2d& p) const {
    return p.x() >= 0.0 && p.y() >= 0.0 && p.x() <= width - 1.0 && p.y() <= height - 1.0;
  }
};

Eigen::Matrix3d LookAt(const Eigen::Vector3d& C, const Eigen::Vector3d& target, double roll) {
  const Eigen::Vector3d f = (target - C).normalized();
  Eigen::Vector3d r = f.cross(Eigen::Vector3d::UnitZ());
  if (r.norm() < 1e-6) r = Eigen::Vector3d::UnitX();
  r.normalize();
  const Eigen::Vector3d d = f.cross(r);
  Eigen::Matrix3d R;
  R.row(0) = r.transpose();
  R.row(1) = d.transpose();
  R.row(2) = f.transpose();
  return Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R;
}

double RotationAngleDeg(const Eigen::Matrix3d& R) {
  const double c = std::clamp(0.5 * (R.trace() - 1.0), -1.0, 1.0);
  return std::acos(c) * 180.0 / kPi;
}

Eigen::Matrix3d DrawIntrinsics(Rng& rng, const SyntheticPairOptions& o, int width, int height) {
  const double fov = DegToRad(rng.Uniform(o.min_fov_deg, o.max_fov_deg));
  const double f = 0.5 * width / std::tan(0.5 * fov);
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  K(0, 0) = K(1, 1) = f;
  K(0, 2) = 0.5 * (width - 1) + rng.Uniform(-1.0, 1.0) * o.principal_point_jitter * width;
  K(1, 2) = 0.5 * (height - 1) + rng.Uniform(-1.0, 1.0) * o.principal_point_jitter * height;
  return K;
}

bool CastPixel(const Scene& s, const Camera& cam, const Eigen::Vector2d& p, Eigen::Vector3d* X, double* z) {
  const Eigen::Vector3d d = cam.Ray(p.x(), p.y());
  double t;
  int surface;
  if (!Cast(s, cam.C, d, &t, &surface)) return false;
  *X = cam.C + t * d;
  *z = t;
  return true;
}

// Is the scene point X (on a surface) the first hit from camera cam?
bool IsVisible(const Scene& s, const Camera& cam, const Eigen::Vector3d& X) {
  double t;
  int surface;
  if (!Cast(s, cam.C, X - cam.C, &t, &surface)) return false;
  return t >= 1.0 - 1e-6;
}

// Co-visible scene point drawn uniformly over image 0; p0/p1 its projections.
bool SampleCovisible(Rng& rng, const Scene& s, const Camera& c0, const Camera& c1, Eigen::Vector3d* X,
                     Eigen::Vector2d* p0, Eigen::Vector2d* p1, double* z0, double* z1) {
  *p0 = Eigen::Vector2d(rng.Uniform(0.0, c0.width - 1.0), rng.Uniform(0.0, c0.height - 1.0));
  if (!CastPixel(s, c0, *p0, X, z0)) return false;
  if (!c1.Project(*X, p1, z1) || !c1.InImage(*p1)) return false;
  return IsVisible(s, c1, *X);
}

// Share of a coarse grid of view-0 surface points that is visible in view 1.
double Overlap(const Scene& s, const Camera& c1, const std::vector<Eigen::Vector3d>& grid) {
  if (grid.empty()) return 0.0;
  int visible = 0;
  for (const Eigen::Vector3d& X : grid) {
    Eigen::Vector2d p;
    double z;
    if (c1.Project(X, &p, &z) && c1.InImage(p) && IsVisible(s, c1, X)) ++visible;
  }
  return static_cast<double>(visible) / grid.size();
}

// Surface points of view 0 on a 16 x 12 grid, their median z-depth, and the share of grid rays that hit something.
double GridPoints(const Scene& s, const Camera& cam, std::vector<Eigen::Vector3d>* grid, double* median_depth) {
  grid->clear();
  std::vector<double> depths;
  const int nx = 16, ny = 12;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const Eigen::Vector2d p((i + 0.5) * (cam.width - 1.0) / nx, (j + 0.5) * (cam.height - 1.0) / ny);
      Eigen::Vector3d X;
      double z;
      if (!CastPixel(s, cam, p, &X, &z)) continue;
      grid->push_back(X);
      depths.push_back(z);
    }
  }
  if (depths.empty()) {
    *median_depth = 0.0;
    return 0.0;
  }
  std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
  *median_depth = depths[depths.size() / 2];
  return static_cast<double>(depths.size()) / (nx * ny);
}

bool PlaceCamera0(Rng& rng, const Scene& s, bool indoor, double max_roll, Camera* cam) {
  const double roll = DegToRad(rng.Uniform(-max_roll, max_roll));
  if (indoor && s.planar) {  // face wall x = 0 from 1.5-5 m, level or looking down at the floor
    const Eigen::Vector3d size = 2.0 * s.room.half;
    const Eigen::Vector3d C(rng.Uniform(1.5, 5.0), rng.Uniform(0.35, 0.65) * size.y(), rng.Uniform(1.1, 1.8));
    const Eigen::Vector3d target(0.0, C.y() + rng.Uniform(-1.0, 1.0), rng.Uniform(0.0, 2.0));
    cam->C = C;
    cam->R = LookAt(C, target, roll);
    return true;
  }
  if (indoor) {
    const Eigen::Vector3d size = 2.0 * s.room.half;
    const Eigen::Vector3d C(rng.Uniform(0.6, size.x() - 0.6), rng.Uniform(0.6, size.y() - 0.6),
                            rng.Uniform(1.1, 1.8));
    if (!IsFree(s, C, 0.5)) return false;
    Eigen::Vector3d target;
    if (!s.boxes.empty() && rng.Uniform() < 0.6) {
      const Box& b = s.boxes[rng.UniformInt(0, static_cast<int>(s.boxes.size()) - 1)];
      target = b.center + Eigen::Vector3d(0.0, 0.0, rng.Uniform(-0.5, 0.5) * b.half.z());
    } else {
      const int wall = rng.UniformInt(0, 3);
      const double z = rng.Uniform(0.3, size.z() - 0.3);
      const double u = rng.Uniform(0.3, (wall < 2 ? size.y() : size.x()) - 0.3);
      if (wall == 0) target = Eigen::Vector3d(0.0, u, z);
      if (wall == 1) target = Eigen::Vector3d(size.x(), u, z);
      if (wall == 2) target = Eigen::Vector3d(u, 0.0, z);
      if (wall == 3) target = Eigen::Vector3d(u, size.y(), z);
    }
    if ((target - C).head<2>().norm() < 1.5) return false;
    cam->C = C;
    cam->R = LookAt(C, target, roll);
    return true;
  }
  const Eigen::Vector3d C(rng.Uniform(-2.0, 2.0), rng.Uniform(-2.0, 2.0), rng.Uniform(1.5, 5.0));
  if (!IsFree(s, C, 1.0)) return false;
  Eigen::Vector3d target;
  const bool at_building = rng.Uniform() < 0.7;
  std::vector<int> buildings;
  for (int i = 0; i < static_cast<int>(s.boxes.size()); ++i) {
    if (s.boxes[i].half.z() > 2.5) buildings.push_back(i);
  }
  if (at_building && !buildings.empty()) {
    const Box& b = s.boxes[buildings[rng.UniformInt(0, static_cast<int>(buildings.size()) - 1)]];
    target = b.center;
    target.z() = rng.Uniform(2.0, std::min(15.0, 2.0 * b.half.z()));
  } else {
    const double angle = rng.Uniform(0.0, 2.0 * kPi);
    target = C + Eigen::Vector3d(60.0 * std::cos(angle), 60.0 * std::sin(angle), 0.0);
    target.z() = rng.Uniform(0.0, 10.0);
  }
  // Keep the pitch within [-20, 15] degrees.
  const double horizontal = (target - C).head<2>().norm();
  if (horizontal < 5.0) return false;
  const double pitch = std::atan2(target.z() - C.z(), horizontal);
  const double clamped = std::clamp(pitch, DegToRad(-20.0), DegToRad(15.0));
  target.z() = C.z() + horizontal * std::tan(clamped);
  cam->C = C;
  cam->R = LookAt(C, target, roll);
  return true;
}

// Places both cameras (intrinsics already set): camera 0 looks at an object/facade, camera 1 is displaced by the
// baseline and looks at the same region plus an extra yaw/tilt. Falls back to the best-overlap pose found if no
// pose meets every constraint (practically never).
void PlacePair(Rng& rng, const Scene& s, const SyntheticPairOptions& o, bool indoor, Camera* c0, Camera* c1) {
  const double free_margin = indoor ? 0.3 : 1.0;
  const double max_rot = o.max_rotation_deg;
  double best_overlap = -1.0;
  Camera best0 = *c0, best1 = *c1;
  std::vector<Eigen::Vector3d> grid;
  for (int outer = 0; outer < 40; ++outer) {
    bool placed = false;
    for (int i = 0; i < 200 && !placed; ++i) placed = PlaceCamera0(rng, s, indoor, o.max_roll_deg, c0);
    if (!placed) continue;
    double median = 0.0;
    const double hit_share = GridPoints(s, *c0, &grid, &median);
    if (hit_share < 0.5 || median <= 0.0) continue;
    const Eigen::Vector3d forward = c0->R.row(2).transpose();
    for (int attempt = 0; attempt < 60; ++attempt) {
      const double baseline = rng.Uniform(o.baseline_min, o.baseline_max) * median;
      Eigen::Vector3d dir(rng.Normal(), rng.Normal(), 0.3 * rng.Normal());
      if (dir.norm() < 1e-9) continue;
      c1->C = c0->C + baseline * dir.normalized();
      if (!IsFree(s, c1->C, free_margin)) continue;
      const Eigen::Vector3d jitter(rng.Uniform(-0.1, 0.1), rng.Uniform(-0.1, 0.1), rng.Uniform(-0.05, 0.05));
      const Eigen::Vector3d look = c0->C + median * forward + median * jitter;
      const double roll = DegToRad(rng.Uniform(-o.max_roll_deg, o.max_roll_deg));
      const double yaw = DegToRad(rng.Uniform(-max_rot, max_rot));
      const double tilt = DegToRad(rng.Uniform(-1.0, 1.0) * std::min(10.0, max_rot));
      c1->R = Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitX()).toRotationMatrix() * LookAt(c1->C, look, roll) *
              Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix().transpose();
      if (RotationAngleDeg(c1->R * c0->R.transpose()) > max_rot) continue;
      const double overlap = Overlap(s, *c1, grid);
      if (overlap >= o.min_overlap) {
        std::vector<Eigen::Vector3d> grid1;
        double median1 = 0.0;
        if (GridPoints(s, *c1, &grid1, &median1) >= 0.5) return;
        continue;
      }
      if (overlap > best_overlap) {
        best_overlap = overlap;
        best0 = *c0;
        best1 = *c1;
      }
    }
  }
  if (best_overlap >= 0.0) {
    *c0 = best0;
    *c1 = best1;
    return;
  }
  // Last resort (never observed): a small sideways step with the same orientation.
  c1->R = c0->R;
  c1->C = c0->C + 0.05 * c0->R.row(0).transpose();
}

// ------------------------------------------------------------------------------------------------------------------
// Depth maps.

// Renders z-depth (0 = no surface) and surface ids (-1) at map resolution; each primitive is only tested inside the
// bounding rectangle of its projection.
void RenderDepth(const Scene& s, const Camera& cam, int mw, int mh, std::vector<double>* depth,
                 std::vector<int>* surface) {
  const size_t n = static_cast<size_t>(mw) * mh;
  depth->assign(n, kInf);
  surface->assign(n, -1);
  const double sx = static_cast<double>(cam.width) / mw, sy = static_cast<double>(cam.height) / mh;
  const Eigen::Matrix3d M = cam.R.transpose() * cam.K_inv;  // world ray of image point (x, y) = M [x y 1]^T
  auto update = [&](size_t i, double t, int id) {
    if (t < (*depth)[i]) {
      (*depth)[i] = t;
      (*surface)[i] = id;
    }
  };
  if (s.has_room || s.has_ground || s.has_background) {
    for (int v = 0; v < mh; ++v) {
      const Eigen::Vector3d row = M.col(1) * ((v + 0.5) * sy - 0.5) + M.col(2);
      for (int u = 0; u < mw; ++u) {
        const Eigen::Vector3d ray = M.col(0) * ((u + 0.5) * sx - 0.5) + row;
        const size_t i = static_cast<size_t>(v) * mw + u;
        double t;
        int id;
        if (s.has_room && IntersectRoom(s, cam.C, ray, &t, &id)) update(i, t, id);
        if (s.has_ground && IntersectGround(s, cam.C, ray, &t, &id)) update(i, t, id);
        if (s.has_background && IntersectBackground(s, cam.C, ray, &t, &id)) update(i, t, id);
      }
    }
  }
  for (const Box& b : s.boxes) {
    // Bounding rectangle of the projection of the box clipped to z >= kNear: the clipped box is the convex hull of
    // its corners in front and of the crossings of its edges with the plane z = kNear.
    constexpr double kNear = 1e-3;
    Eigen::Vector3d corners[8];
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d local((k & 1 ? 1 : -1) * b.half.x(), (k & 2 ? 1 : -1) * b.half.y(),
                                  (k & 4 ? 1 : -1) * b.half.z());
      corners[k] = cam.R * (b.center + ToWorld(b, local) - cam.C);
    }
    double umin = kInf, umax = -kInf, vmin = kInf, vmax = -kInf;
    auto add = [&](const Eigen::Vector3d& Xc) {
      const Eigen::Vector3d h = cam.K * Xc;
      const double u = (h.x() / h.z() + 0.5) / sx - 0.5, v = (h.y() / h.z() + 0.5) / sy - 0.5;
      umin = std::min(umin, u), umax = std::max(umax, u), vmin = std::min(vmin, v), vmax = std::max(vmax, v);
    };
    for (int k = 0; k < 8; ++k) {
      if (corners[k].z() >= kNear) add(corners[k]);
      for (int axis = 0; axis < 3; ++axis) {  // edges k -> k | bit
        const int bit = 1 << axis;
        if (k & bit) continue;
        const Eigen::Vector3d& A = corners[k];
        const Eigen::Vector3d& B = corners[k | bit];
        if ((A.z() < kNear) != (B.z() < kNear)) add(A + (kNear - A.z()) / (B.z() - A.z()) * (B - A));
      }
    }
    if (!(umin <= umax) || umax < -1.0 || vmax < -1.0 || umin > mw || vmin > mh) continue;
    const int u0 = static_cast<int>(std::max(0.0, std::floor(umin) - 1.0));
    const int u1 = static_cast<int>(std::min(mw - 1.0, std::ceil(umax) + 1.0));
    const int v0 = static_cast<int>(std::max(0.0, std::floor(vmin) - 1.0));
    const int v1 = static_cast<int>(std::min(mh - 1.0, std::ceil(vmax) + 1.0));
    // In the box frame: origin lo, ray direction Mb [x y 1]^T.
    const Eigen::Vector3d lo = ToLocal(b, cam.C - b.center);
    Eigen::Matrix3d Mb;
    for (int k = 0; k < 3; ++k) Mb.col(k) = ToLocal(b, M.col(k));
    for (int v = v0; v <= v1; ++v) {
      const Eigen::Vector3d row = Mb.col(1) * ((v + 0.5) * sy - 0.5) + Mb.col(2);
      for (int u = u0; u <= u1; ++u) {
        const Eigen::Vector3d ld = Mb.col(0) * ((u + 0.5) * sx - 0.5) + row;
        double tn, tf;
        int fn, ff;
        if (SlabsLocal(b.half, lo, ld, &tn, &fn, &tf, &ff) && tn > kMinT) {
          update(static_cast<size_t>(v) * mw + u, tn, b.first_surface + fn);
        }
      }
    }
  }
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite((*depth)[i])) (*depth)[i] = 0.0;
  }
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

// Median of values[i] over a regular subsample (at most ~20000) of the indices i with mask[i] > 0; 0 if none.
double SubsampledMedian(const std::vector<double>& values, const std::vector<double>& mask) {
  const size_t stride = 1 + values.size() / 20000;
  std::vector<double> kept;
  kept.reserve(values.size() / stride + 1);
  for (size_t i = 0; i < values.size(); i += stride) {
    if (mask[i] > 0.0) kept.push_back(values[i]);
  }
  return Median(std::move(kept));
}

void GaussianBlur(double sigma, int w, int h, std::vector<double>* image) {
  if (sigma <= 0.0) return;
  const int radius = std::max(1, static_cast<int>(std::ceil(3.0 * sigma)));
  std::vector<double> kernel(2 * radius + 1);
  double sum = 0.0;
  for (int k = -radius; k <= radius; ++k) sum += kernel[k + radius] = std::exp(-0.5 * k * k / (sigma * sigma));
  for (double& k : kernel) k /= sum;
  // Horizontal pass through a row padded by edge replication, then a vertical pass over whole rows.
  std::vector<double> padded(w + 2 * radius), tmp(image->size());
  for (int y = 0; y < h; ++y) {
    const double* row = image->data() + static_cast<size_t>(y) * w;
    for (int x = 0; x < w + 2 * radius; ++x) padded[x] = row[std::clamp(x - radius, 0, w - 1)];
    double* out = tmp.data() + static_cast<size_t>(y) * w;
    std::fill(out, out + w, 0.0);
    for (int k = 0; k <= 2 * radius; ++k) {
      const double weight = kernel[k];
      const double* src = padded.data() + k;
      for (int x = 0; x < w; ++x) out[x] += weight * src[x];
    }
  }
  for (int y = 0; y < h; ++y) {
    double* out = image->data() + static_cast<size_t>(y) * w;
    std::fill(out, out + w, 0.0);
    for (int k = -radius; k <= radius; ++k) {
      const double* row = tmp.data() + static_cast<size_t>(std::clamp(y + k, 0, h - 1)) * w;
      const double weight = kernel[k + radius];
      for (int x = 0; x < w; ++x) out[x] += weight * row[x];
    }
  }
}

struct PriorView {
  DepthMap prior, true_depth;
  std::vector<uint8_t> wild;
  double scale = 1.0, shift = 0.0, median_depth = 0.0;
};

// Renders the true depth of a view and turns it into a corrupted prior (steps 1-6 of the header).
// reference_scale > 0: draw a = reference_scale * r, r log-uniform within c.max_scale_ratio (see the header);
// metric: nearly metric priors (a in [0.8, 1.25], |b| <= 5% of the median).
PriorView MakePrior(Rng& rng, const Scene& s, const Camera& cam, int mw, int mh, const DepthPriorCorruption& c,
                    double reference_scale, bool metric) {
  PriorView out;
  std::vector<double> z;
  std::vector<int> surface;
  RenderDepth(s, cam, mw, mh, &z, &surface);
  const size_t n = z.size();
  out.median_depth = SubsampledMedian(z, z);
  const double median = out.median_depth > 0.0 ? out.median_depth : 1.0;

  // Per-view strengths drawn from their ranges.
  const double distortion =
      c.max_distortion > c.distortion ? rng.Uniform(c.distortion, c.max_distortion) : c.distortion;
  const double offset_sigma = c.max_surface_offset_sigma > c.surface_offset_sigma
                                  ? rng.Uniform(c.surface_offset_sigma, c.max_surface_offset_sigma)
                                  : c.surface_offset_sigma;
  // 1. per-surface relative scales and offsets.
  std::vector<double> surface_scale(s.num_surfaces), surface_offset(s.num_surfaces);
  for (int i = 0; i < s.num_surfaces; ++i) {
    surface_scale[i] = 1.0 + c.surface_scale_sigma * rng.Normal();
    surface_offset[i] = offset_sigma * median * rng.Normal();
  }
  // 2. smooth distortion: eps(u, v) = polynomial + sinusoid in normalised map coordinates, and a monotone
  // compression (gamma > 0: expansion) of the depth range around the median.
  double poly[5];
  const double weights[5] = {0.5, 0.5, 0.25, 0.25, 0.25};  // u, v, uv, u^2 - 1/3, v^2 - 1/3
  for (int k = 0; k < 5; ++k) poly[k] = distortion * weights[k] * rng.Uniform(-1.0, 1.0);
  const double sin_amp = 0.5 * distortion * rng.Uniform(-1.0, 1.0);
  const double sin_freq = rng.Uniform(0.5, 1.5), sin_dir = rng.Uniform(0.0, 2.0 * kPi);
  const double sin_phase = rng.Uniform(0.0, 2.0 * kPi);
  const double gamma = distortion * rng.Uniform(-1.0, 1.0);
  const double ku = kPi * sin_freq * std::cos(sin_dir), kv = kPi * sin_freq * std::sin(sin_dir);
  std::vector<double> su(mw), cu(mw), sv(mh), cv(mh);
  for (int x = 0; x < mw; ++x) {
    const double u = mw > 1 ? 2.0 * x / (mw - 1) - 1.0 : 0.0;
    su[x] = std::sin(ku * u + sin_phase), cu[x] = std::cos(ku * u + sin_phase);
  }
  for (int y = 0; y < mh; ++y) {
    const double v = mh > 1 ? 2.0 * y / (mh - 1) - 1.0 : 0.0;
    sv[y] = std::sin(kv * v), cv[y] = std::cos(kv * v);
  }
  // 3. wildly wrong blobs.
  out.wild.assign(n, 0);
  double wild_factor[4] = {1.0, 1.0, 1.0, 1.0};  // indexed by out.wild (0 = not wild, k = blob k)
  if (c.wild_region_fraction > 0.0) {
    const int blobs = rng.UniformInt(1, 3);
    const double area = c.wild_region_fraction * mw * mh / blobs;
    for (int k = 0; k < blobs; ++k) {
      const double aspect = rng.LogUniform(0.5, 2.0);
      const double a = std::sqrt(area / (kPi * aspect)), b = aspect * a;
      const double cx = rng.Uniform(0.0, mw), cy = rng.Uniform(0.0, mh), th = rng.Uniform(0.0, kPi);
      wild_factor[k + 1] = std::exp((rng.Uniform() < 0.5 ? -1.0 : 1.0) * rng.Uniform(std::log(1.5), std::log(4.0)));
      const double ct = std::cos(th), st = std::sin(th);
      const double reach = std::max(a, b);
      const int x0 = std::max(0, static_cast<int>(cx - reach)), x1 = std::min(mw - 1, static_cast<int>(cx + reach));
      const int y0 = std::max(0, static_cast<int>(cy - reach)), y1 = std::min(mh - 1, static_cast<int>(cy + reach));
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          const double dx = x + 0.5 - cx, dy = y + 0.5 - cy;
          const double p = (ct * dx + st * dy) / a, q = (-st * dx + ct * dy) / b;
          if (p * p + q * q > 1.0) continue;
          const size_t i = static_cast<size_t>(y) * mw + x;
          if (!out.wild[i]) out.wild[i] = static_cast<uint8_t>(k + 1);  // overlapping blobs keep the first one
        }
      }
    }
  }
  // Corrupted depth (metres) per pixel: steps 1-4.
  std::vector<double> q(n);
  const double noise_halfwidth = std::sqrt(3.0) * c.noise;  // uniform noise with std. dev. c.noise
  const uint64_t noise_seed = static_cast<uint64_t>(rng.Uniform() * 0x1.0p53);
  for (int y = 0; y < mh; ++y) {
    const double v = mh > 1 ? 2.0 * y / (mh - 1) - 1.0 : 0.0;
    for (int x = 0; x < mw; ++x) {
      const size_t i = static_cast<size_t>(y) * mw + x;
      const double u = mw > 1 ? 2.0 * x / (mw - 1) - 1.0 : 0.0;
      double d;
      if (z[i] > 0.0) {
        d = std::max(0.2 * z[i], surface_scale[surface[i]] * z[i] + surface_offset[surface[i]]);
        const double eps = poly[0] * u + poly[1] * v + poly[2] * u * v + poly[3] * (u * u - 1.0 / 3.0) +
                           poly[4] * (v * v - 1.0 / 3.0) + sin_amp * (su[x] * cv[y] + cu[x] * sv[y]);
        d *= std::max(0.2, 1.0 + eps);
        const double r = z[i] / median;
        d *= std::max(0.2, 1.0 + 2.0 * gamma * (r - 1.0) / (r + 1.0));
      } else {
        d = s.sky_depth;
      }
      d *= wild_factor[out.wild[i]];
      if (noise_halfwidth > 0.0) {  // a cheap counter-based generator per pixel
        const double unit = static_cast<double>(SplitMix64(noise_seed + i) >> 11) * 0x1.0p-53;
        d *= std::max(0.5, 1.0 + noise_halfwidth * (2.0 * unit - 1.0));
      }
      q[i] = c.type == SyntheticPriorType::kDepth ? d : 1.0 / d;
    }
  }
  // 5. the unknown affine transform into the output space, keeping every prior positive.
  const double q_min = *std::min_element(q.begin(), q.end());
  const double q_median = out.median_depth > 0.0 ? SubsampledMedian(q, z) : SubsampledMedian(q, q);
  double a;
  if (metric) {
    a = rng.LogUniform(0.8, 1.25);
  } else if (reference_scale > 0.0 && c.max_scale_ratio > 0.0) {
    a = reference_scale * rng.LogUniform(1.0 / c.max_scale_ratio, c.max_scale_ratio);
  } else {
    a = rng.LogUniform(c.min_scale, c.max_scale);
  }
  const double shift_fraction = metric ? std::min(0.05, c.max_shift_fraction) : c.max_shift_fraction;
  const double lower = -shift_fraction * q_median;
  const double upper = std::min(shift_fraction * q_median, 0.9 * q_min);
  const double b = rng.Uniform(lower, upper);
  for (double& v : q) v = (v - b) / a;
  // 6. blur (of the log prior: multiplicative smearing).
  if (c.blur_log_depth) {
    for (double& v : q) v = std::log(v);
    GaussianBlur(c.blur_sigma_px, mw, mh, &q);
    for (double& v : q) v = std::exp(v);
  } else {
    GaussianBlur(c.blur_sigma_px, mw, mh, &q);
  }

  out.scale = a;
  out.shift = b;
  out.prior.width = out.true_depth.width = mw;
  out.prior.height = out.true_depth.height = mh;
  out.prior.data.assign(q.begin(), q.end());
  out.true_depth.data.assign(z.begin(), z.end());
  for (uint8_t& w : out.wild) w = w ? 1 : 0;
  return out;
}

void ThrowIf(bool condition, const char* message) {
  if (condition) throw std::invalid_argument(std::string("SyntheticPairOptions: ") + message);
}

}  // namespace

// ------------------------------------------------------------------------------------------------------------------

DepthPriorCorruption DepthPriorCorruption::AffineOnly() {
  DepthPriorCorruption c;
  c.distortion = 0.0;
  c.surface_scale_sigma = 0.0;
  c.surface_offset_sigma = 0.0;
  c.wild_region_fraction = 0.0;
  c.noise = 0.0;
  c.blur_sigma_px = 0.0;
  return c;
}

DepthPriorCorruption DepthPriorCorruption::Bad() {
  DepthPriorCorruption c;
  c.distortion = 0.4;
  c.surface_scale_sigma = 0.15;
  c.surface_offset_sigma = 0.25;
  c.wild_region_fraction = 0.2;
  c.noise = 0.03;
  c.blur_sigma_px = 3.0;
  return c;
}

void SyntheticPairOptions::Check() const {
  ThrowIf(image_width < 0 || image_height < 0, "image_width/image_height must be >= 0 (0 = scene default)");
  ThrowIf((image_width == 0) != (image_height == 0), "set both image_width and image_height or neither");
  ThrowIf(image_width != 0 && (image_width < 16 || image_height < 16), "images must be at least 16 x 16");
  ThrowIf(!(depth_map_scale >= 0.0 && depth_map_scale <= 1.0), "depth_map_scale must be in (0, 1] or 0");
  ThrowIf(!(min_fov_deg > 1.0 && min_fov_deg <= max_fov_deg && max_fov_deg < 170.0),
          "need 1 < min_fov_deg <= max_fov_deg < 170");
  ThrowIf(!(principal_point_jitter >= 0.0 && principal_point_jitter <= 0.2), "principal_point_jitter in [0, 0.2]");
  ThrowIf(!(baseline_min > 0.0 && baseline_min <= baseline_max && baseline_max <= 2.0),
          "need 0 < baseline_min <= baseline_max <= 2");
  ThrowIf(!(max_rotation_deg >= 0.0 && max_rotation_deg <= 90.0), "max_rotation_deg in [0, 90]");
  ThrowIf(!(max_roll_deg >= 0.0 && max_roll_deg <= 45.0), "max_roll_deg in [0, 45]");
  ThrowIf(!(min_overlap >= 0.0 && min_overlap <= 1.0), "min_overlap in [0, 1]");
  ThrowIf(num_matches < 0, "num_matches must be >= 0");
  ThrowIf(max_num_matches < 0, "max_num_matches must be >= 0 (0 = num_matches)");
  ThrowIf(!(min_edge_fraction >= 0.0 && min_edge_fraction <= max_edge_fraction && max_edge_fraction <= 1.0),
          "need 0 <= min_edge_fraction <= max_edge_fraction <= 1");
  ThrowIf(!(min_outlier_ratio >= 0.0 && min_outlier_ratio <= max_outlier_ratio && max_outlier_ratio < 1.0),
          "need 0 <= min_outlier_ratio <= max_outlier_ratio < 1");
  ThrowIf(!(mismatch_fraction >= 0.0 && mismatch_fraction <= 1.0), "mismatch_fraction in [0, 1]");
  ThrowIf(!(outlier_min_offset_px >= 0.0), "outlier_min_offset_px must be >= 0");
  ThrowIf(!(min_pixel_noise >= 0.0 && min_pixel_noise <= max_pixel_noise), "need 0 <= min_pixel_noise <= max");
  const DepthPriorCorruption& c = prior;
  ThrowIf(!(c.min_scale > 0.0 && c.min_scale <= c.max_scale && std::isfinite(c.max_scale)),
          "need 0 < prior.min_scale <= prior.max_scale");
  ThrowIf(!(c.max_shift_fraction >= 0.0 && c.max_shift_fraction <= 10.0), "prior.max_shift_fraction in [0, 10]");
  ThrowIf(!(c.distortion >= 0.0 && c.distortion <= 1.0), "prior.distortion in [0, 1]");
  ThrowIf(!(c.surface_scale_sigma >= 0.0 && c.surface_offset_sigma >= 0.0), "prior surface sigmas must be >= 0");
  ThrowIf(!(c.wild_region_fraction >= 0.0 && c.wild_region_fraction <= 0.5), "prior.wild_region_fraction in [0, .5]");
  ThrowIf(!(c.noise >= 0.0 && c.noise <= 0.25), "prior.noise in [0, 0.25]");
  ThrowIf(!(c.blur_sigma_px >= 0.0 && c.blur_sigma_px <= 50.0), "prior.blur_sigma_px in [0, 50]");
  ThrowIf(!(c.max_distortion >= 0.0 && c.max_distortion <= 1.0), "prior.max_distortion in [0, 1]");
  ThrowIf(!(c.max_surface_offset_sigma >= 0.0), "prior.max_surface_offset_sigma must be >= 0");
  ThrowIf(!(c.max_scale_ratio == 0.0 || c.max_scale_ratio >= 1.0), "prior.max_scale_ratio must be 0 or >= 1");
  ThrowIf(!(c.metric_fraction >= 0.0 && c.metric_fraction <= 1.0), "prior.metric_fraction in [0, 1]");
}

AffineDepthPose SyntheticPair::TrueModel() const {
  AffineDepthPose m;
  const Eigen::Matrix4d T = pair.T_0to1.value_or(Eigen::Matrix4d::Identity());
  m.R = T.block<3, 3>(0, 0);
  const Eigen::Vector3d t = T.block<3, 1>(0, 3);
  if (prior_type == SyntheticPriorType::kDepth) {
    m.t = t / prior_scale0;
    m.scale = prior_scale1 / prior_scale0;
    m.shift0 = prior_shift0 / prior_scale0;
    m.shift1 = prior_shift1 / prior_scale1;
  } else {
    m.t = t * prior_scale0;
    m.scale = prior_scale0 / prior_scale1;
    m.shift0 = m.shift1 = 0.0;
  }
  m.f0 = focal0;
  m.f1 = focal1;
  return m;
}

SyntheticPair GenerateTwoViewPair(const SyntheticPairOptions& options, uint64_t seed) {
  options.Check();
  Rng rng(seed);
  const bool indoor = options.scene != SyntheticSceneType::kOutdoor;  // kPlanar is an (empty) room
  const int width = options.image_width > 0 ? options.image_width : (indoor ? 640 : 1024);
  const int height = options.image_height > 0 ? options.image_height : (indoor ? 480 : 768);
  const double map_scale = options.depth_map_scale > 0.0 ? options.depth_map_scale : (indoor ? 0.5 : 0.25);
  const int mw = std::max(1, static_cast<int>(std::lround(width * map_scale)));
  const int mh = std::max(1, static_cast<int>(std::lround(height * map_scale)));

  Scene scene;
  if (options.scene == SyntheticSceneType::kPlanar) {
    BuildPlanarScene(rng, &scene);
  } else if (indoor) {
    BuildIndoorScene(rng, &scene);
  } else {
    BuildOutdoorScene(rng, &scene);
  }

  Camera cam[2];
  cam[0].width = cam[1].width = width;
  cam[0].height = cam[1].height = height;
  cam[0].K = DrawIntrinsics(rng, options, width, height);
  const bool one_camera = options.camera_setup == SyntheticCameraSetup::kSharedFocal ||
                          (options.camera_setup == SyntheticCameraSetup::kCalibrated && options.calibrated_same_camera);
  cam[1].K = one_camera ? cam[0].K : DrawIntrinsics(rng, options, width, height);
  for (Camera& c : cam) c.K_inv = c.K.inverse();
  PlacePair(rng, scene, options, indoor, &cam[0], &cam[1]);

  SyntheticPair out;
  out.scene = options.scene;
  out.camera_setup = options.camera_setup;
  out.prior_type = options.prior.type;
  out.focal0 = cam[0].K(0, 0);
  out.focal1 = cam[1].K(0, 0);
  const Eigen::Matrix3d R = cam[1].R * cam[0].R.transpose();
  const Eigen::Vector3d t = cam[1].R * (cam[0].C - cam[1].C);
  out.rotation_deg = RotationAngleDeg(R);
  out.baseline = (cam[1].C - cam[0].C).norm();

  PairData& pair = out.pair;
  pair.path = "synthetic:" + std::to_string(seed);
  pair.K0 = cam[0].K;
  pair.K1 = cam[1].K;
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.block<3, 3>(0, 0) = R;
  T.block<3, 1>(0, 3) = t;
  pair.T_0to1 = T;
  pair.width0 = pair.width1 = width;
  pair.height0 = pair.height1 = height;

  // Matches.
  const double ratio = rng.Uniform(options.min_outlier_ratio, options.max_outlier_ratio);
  const int num_matches = options.max_num_matches > options.num_matches
                              ? rng.UniformInt(options.num_matches, options.max_num_matches)
                              : options.num_matches;
  int num_outliers = static_cast<int>(std::lround(ratio * num_matches));
  int num_inliers = num_matches - num_outliers;
  out.pixel_noise = rng.Uniform(options.min_pixel_noise, options.max_pixel_noise);
  // Depth-edge pixels of view 0 (map resolution) for the keypoints on object boundaries.
  std::vector<int> edge_pixels;
  int num_edge_inliers = 0;
  if (options.max_edge_fraction > 0.0) {
    const double edge_fraction = rng.Uniform(options.min_edge_fraction, options.max_edge_fraction);
    std::vector<double> z;
    std::vector<int> surface;
    RenderDepth(scene, cam[0], mw, mh, &z, &surface);
    auto jump = [&](size_t i, size_t j) {
      return z[i] > 0.0 && z[j] > 0.0 && std::abs(z[i] - z[j]) > 0.05 * std::min(z[i], z[j]);
    };
    for (int v = 0; v < mh; ++v) {
      for (int u = 0; u < mw; ++u) {
        const size_t i = static_cast<size_t>(v) * mw + u;
        if ((u + 1 < mw && jump(i, i + 1)) || (v + 1 < mh && jump(i, i + mw)) || (u > 0 && jump(i, i - 1)) ||
            (v > 0 && jump(i, i - mw))) {
          edge_pixels.push_back(static_cast<int>(i));
        }
      }
    }
    if (!edge_pixels.empty()) num_edge_inliers = static_cast<int>(std::lround(edge_fraction * num_inliers));
  }

  struct Match {
    Eigen::Vector2d p0, p1;
    Eigen::Vector3d X0 = Eigen::Vector3d::Zero();
    double z0 = 0.0, z1 = 0.0;
    bool inlier = false;
  };
  std::vector<Match> matches;
  matches.reserve(num_matches);
  const long max_attempts = 2000 + 200L * num_inliers;
  const double map_px_x = static_cast<double>(width) / mw, map_px_y = static_cast<double>(height) / mh;
  for (long attempt = 0; attempt < max_attempts && static_cast<int>(matches.size()) < num_inliers; ++attempt) {
    Match m;
    Eigen::Vector3d X;
    if (static_cast<int>(matches.size()) < num_edge_inliers && attempt < max_attempts / 2) {
      // Within one map pixel of a depth edge.
      const int i = edge_pixels[rng.UniformInt(0, static_cast<int>(edge_pixels.size()) - 1)];
      const double u = i % mw, v = i / mw;
      m.p0 = Eigen::Vector2d((u + 0.5 + rng.Uniform(-1.0, 1.0)) * map_px_x - 0.5,
                             (v + 0.5 + rng.Uniform(-1.0, 1.0)) * map_px_y - 0.5);
      if (!cam[0].InImage(m.p0) || !CastPixel(scene, cam[0], m.p0, &X, &m.z0)) continue;
      if (!cam[1].Project(X, &m.p1, &m.z1) || !cam[1].InImage(m.p1) || !IsVisible(scene, cam[1], X)) continue;
    } else if (!SampleCovisible(rng, scene, cam[0], cam[1], &X, &m.p0, &m.p1, &m.z0, &m.z1)) {
      continue;
    }
    m.X0 = cam[0].R * (X - cam[0].C);
    m.inlier = true;
    matches.push_back(m);
  }
  if (static_cast<int>(matches.size()) < num_inliers) {  // tiny overlap: keep the requested ratio
    num_inliers = static_cast<int>(matches.size());
    num_outliers = static_cast<int>(std::lround(num_inliers * ratio / (1.0 - ratio)));
  }
  const double min_offset2 = options.outlier_min_offset_px * options.outlier_min_offset_px;
  for (int k = 0; k < num_outliers; ++k) {
    Match m;
    bool done = false;
    if (num_inliers > 0 && rng.Uniform() < options.mismatch_fraction) {  // mismatched features
      for (int attempt = 0; attempt < 200 && !done; ++attempt) {
        Eigen::Vector3d XA, XB;
        Eigen::Vector2d pA0, pA1, pB0, pB1;
        double zA0, zA1, zB0, zB1;
        if (!SampleCovisible(rng, scene, cam[0], cam[1], &XA, &pA0, &pA1, &zA0, &zA1)) continue;
        if (!SampleCovisible(rng, scene, cam[0], cam[1], &XB, &pB0, &pB1, &zB0, &zB1)) continue;
        if ((pB1 - pA1).squaredNorm() < min_offset2) continue;
        m.p0 = pA0;
        m.p1 = pB1;
        done = true;
      }
    }
    for (int attempt = 0; attempt < 1000 && !done; ++attempt) {  // a random pixel in image 1
      const Eigen::Vector2d p0(rng.Uniform(0.0, width - 1.0), rng.Uniform(0.0, height - 1.0));
      const Eigen::Vector2d p1(rng.Uniform(0.0, width - 1.0), rng.Uniform(0.0, height - 1.0));
      Eigen::Vector3d X;
      double z0;
      if (!CastPixel(scene, cam[0], p0, &X, &z0)) continue;
      Eigen::Vector2d proj;
      double z1;
      if (cam[1].Project(X, &proj, &z1) && (proj - p1).squaredNorm() < min_offset2) continue;
      m.p0 = p0;
      m.p1 = p1;
      done = true;
    }
    if (!done) {  // image 0 sees almost no surface (never observed): a random pair far from anything
      m.p0 = Eigen::Vector2d(rng.Uniform(0.0, width - 1.0), rng.Uniform(0.0, height - 1.0));
      m.p1 = Eigen::Vector2d(rng.Uniform(0.0, width - 1.0), rng.Uniform(0.0, height - 1.0));
    }
    matches.push_back(m);
  }
  for (int i = static_cast<int>(matches.size()) - 1; i > 0; --i) std::swap(matches[i], matches[rng.UniformInt(0, i)]);

  const size_t n = matches.size();
  pair.p0.resize(n);
  pair.p1.resize(n);
  out.is_inlier.resize(n);
  out.points0.resize(n);
  out.true_depth0.resize(n);
  out.true_depth1.resize(n);
  out.p0_clean.resize(n);
  out.p1_clean.resize(n);
  auto noisy = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d e(rng.TruncatedNormal(3.0), rng.TruncatedNormal(3.0));
    const Eigen::Vector2d q = p + out.pixel_noise * e;
    return Eigen::Vector2d(std::clamp(q.x(), -0.5, width - 0.5), std::clamp(q.y(), -0.5, height - 0.5));
  };
  for (size_t i = 0; i < n; ++i) {
    const Match& m = matches[i];
    pair.p0[i] = noisy(m.p0);
    pair.p1[i] = noisy(m.p1);
    out.p0_clean[i] = m.p0;
    out.p1_clean[i] = m.p1;
    out.is_inlier[i] = m.inlier ? 1 : 0;
    out.points0[i] = m.X0;
    out.true_depth0[i] = m.z0;
    out.true_depth1[i] = m.z1;
    out.num_inliers += m.inlier ? 1 : 0;
  }
  out.outlier_ratio = n > 0 ? 1.0 - static_cast<double>(out.num_inliers) / n : 0.0;

  // Depth priors.
  const bool metric = options.prior.metric_fraction > 0.0 && rng.Uniform() < options.prior.metric_fraction;
  PriorView view0 = MakePrior(rng, scene, cam[0], mw, mh, options.prior, 0.0, metric);
  PriorView view1 = MakePrior(rng, scene, cam[1], mw, mh, options.prior, view0.scale, metric);
  out.prior_scale0 = view0.scale;
  out.prior_shift0 = view0.shift;
  out.prior_scale1 = view1.scale;
  out.prior_shift1 = view1.shift;
  out.median_depth0 = view0.median_depth;
  out.median_depth1 = view1.median_depth;
  pair.depth0 = std::move(view0.prior);
  pair.depth1 = std::move(view1.prior);
  out.true_depth_map0 = std::move(view0.true_depth);
  out.true_depth_map1 = std::move(view1.true_depth);
  out.wild_mask0 = std::move(view0.wild);
  out.wild_mask1 = std::move(view1.wild);
  return out;
}

std::vector<SyntheticPair> GenerateTwoViewSet(const SyntheticPairOptions& options, int count, uint64_t seed) {
  options.Check();
  std::vector<SyntheticPair> pairs;
  pairs.reserve(std::max(0, count));
  for (int i = 0; i < count; ++i) {
    pairs.push_back(GenerateTwoViewPair(options, SplitMix64(seed ^ SplitMix64(static_cast<uint64_t>(i) + 1))));
  }
  return pairs;
}

std::vector<std::string> SyntheticPairPresetNames() {
  return {"indoor_calibrated",
          "outdoor_calibrated",
          "indoor_shared_focal",
          "indoor_two_focal",
          "outdoor_two_focal",
          "indoor_bad_prior",
          "hard_indoor_calibrated",
          "hard_outdoor_calibrated",
          "hard_planar_calibrated",
          "hard_indoor_shared_focal",
          "hard_outdoor_shared_focal",
          "hard_planar_shared_focal",
          "hard_indoor_two_focal",
          "hard_outdoor_two_focal",
          "hard_low_parallax_calibrated",
          "hard_low_parallax_shared_focal"};
}

namespace {

std::optional<SyntheticPairOptions> HardPreset(const std::string& name) {
  SyntheticPairOptions o;
  const std::string rest = name.substr(5);  // after "hard_"
  std::string setup;
  if (rest.rfind("indoor_", 0) == 0) {
    o.scene = SyntheticSceneType::kIndoor;
    setup = rest.substr(7);
  } else if (rest.rfind("outdoor_", 0) == 0) {
    o.scene = SyntheticSceneType::kOutdoor;
    setup = rest.substr(8);
  } else if (rest.rfind("planar_", 0) == 0) {
    o.scene = SyntheticSceneType::kPlanar;
    setup = rest.substr(7);
  } else if (rest.rfind("low_parallax_", 0) == 0) {
    o.scene = SyntheticSceneType::kIndoor;
    o.baseline_min = 0.005;
    o.baseline_max = 0.03;
    setup = rest.substr(13);
  } else {
    return std::nullopt;
  }
  if (setup == "calibrated") {
    o.camera_setup = SyntheticCameraSetup::kCalibrated;
    o.calibrated_same_camera = false;
  } else if (setup == "shared_focal") {
    o.camera_setup = SyntheticCameraSetup::kSharedFocal;
  } else if (setup == "two_focal") {
    o.camera_setup = SyntheticCameraSetup::kTwoFocal;
  } else {
    return std::nullopt;
  }
  const bool outdoor = o.scene == SyntheticSceneType::kOutdoor;
  o.image_width = outdoor ? 1024 : 640;
  o.image_height = outdoor ? 768 : 480;
  o.depth_map_scale = 0.5;
  o.min_fov_deg = 50.0;
  o.max_fov_deg = 100.0;
  o.num_matches = 150;
  o.max_num_matches = 2000;
  o.min_pixel_noise = 0.5;
  o.max_pixel_noise = 1.5;
  o.min_outlier_ratio = 0.1;
  o.max_outlier_ratio = 0.6;
  o.min_edge_fraction = 0.03;
  o.max_edge_fraction = 0.15;
  DepthPriorCorruption& c = o.prior;
  c.max_scale_ratio = 2.0;
  c.metric_fraction = 0.5;
  c.distortion = 0.02;
  c.max_distortion = 0.10;
  c.surface_offset_sigma = 0.01;
  c.max_surface_offset_sigma = 0.05;
  c.blur_log_depth = true;
  return o;
}

}  // namespace

std::optional<SyntheticPairOptions> SyntheticPairPreset(const std::string& name) {
  if (name.rfind("hard_", 0) == 0) return HardPreset(name);
  SyntheticPairOptions o;
  o.scene = name.rfind("outdoor", 0) == 0 ? SyntheticSceneType::kOutdoor : SyntheticSceneType::kIndoor;
  o.image_width = o.scene == SyntheticSceneType::kIndoor ? 640 : 1024;
  o.image_height = o.scene == SyntheticSceneType::kIndoor ? 480 : 768;
  o.depth_map_scale = o.scene == SyntheticSceneType::kIndoor ? 0.5 : 0.25;
  if (name == "indoor_calibrated" || name == "outdoor_calibrated") {
    o.camera_setup = SyntheticCameraSetup::kCalibrated;
  } else if (name == "indoor_shared_focal") {
    o.camera_setup = SyntheticCameraSetup::kSharedFocal;
  } else if (name == "indoor_two_focal" || name == "outdoor_two_focal") {
    o.camera_setup = SyntheticCameraSetup::kTwoFocal;
  } else if (name == "indoor_bad_prior") {
    o.camera_setup = SyntheticCameraSetup::kCalibrated;
    o.prior = DepthPriorCorruption::Bad();
  } else {
    return std::nullopt;
  }
  return o;
}

}  // namespace madsfm
