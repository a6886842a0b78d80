#pragma once
// A run recorded for the viewer (view/html.h): what to draw (the scene's bodies by their shapes,
// or boxes from their inertia, its joints and anchors) once, then decimated frames of the
// stepped bodies' poses, the contacts with their impulses, and the joints' separation and
// penetration, as compact arrays. Frames are taken at most `frame_rate` times per simulated
// second; when there are more than `max_frames`, every other one is dropped and the period
// doubles, so a run of any length fits in a bounded file without knowing its length ahead.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ldlpgs/physics/shatter.h"
#include "ldlpgs/physics/step.h"

namespace ldlpgs::view {

struct RecordOptions {
  double frame_rate = 30;  // frames per simulated second at most (the page interpolates between them)
  int max_frames = 2000;   // beyond this the period doubles (about 30 bytes per body and frame)
};

// One drawn solid, fixed to a stepped body (an index of the stepped mechanism) at a pose in its frame.
struct Solid {
  int body = 0;
  int group = 0;                  // the scene's body it belongs to: shards of one body share it (its colour)
  ShapeType type = ShapeType::box;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               // body frame
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // solid -> body frame
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  // box, ellipsoid: half extents; sphere: radius; capsule,
                                                   // cylinder: radius, half length; plane: normal (hulls and
                                                   // heightfields are drawn as their bounding boxes)
  bool from_inertia = false;      // a box standing in for a body without shapes
};

// One of the scene's constraints: its anchors and axis in each body's frame (stepped bodies).
struct Joint {
  ConstraintType type = ConstraintType::ball;
  int body_a = 0, body_b = 0;
  Eigen::Vector3d anchor_a = Eigen::Vector3d::Zero(), anchor_b = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_a = Eigen::Vector3d::UnitZ();  // the frame's n column (hinge, prismatic, ...)
};

// The half extents of the uniform box of this mass with these principal moments:
// I_x = m (b^2 + c^2) / 3, so a^2 = 3 (I_y + I_z - I_x) / (2 m). Moments that no box has (the
// triangle inequality broken) give a thin side of a hundredth of the longest.
Eigen::Vector3d box_from_inertia(double mass, const Eigen::Vector3d& inertia);

class Recording {
 public:
  // `original`: the scene as loaded; `shattered`: what shatter() made of it and is stepped (with
  // nothing shattered, its mechanism is the original and every body its own shard). Takes the
  // initial pose as frame 0.
  Recording(const Mechanism& original, const ShatterResult& shattered, const RecordOptions& options = {});
  // From a simulation's current state on (its mechanism as it is: no shards), frame 0 at its time.
  explicit Recording(const Simulation& sim, const RecordOptions& options = {});
  // After every step of `sim` (stepping the shattered mechanism): a frame when its time is due.
  void add(const Simulation& sim, const StepReport& report);
  // The last state as a frame, if it is not one yet (a run's end between two due times).
  void finish(const Simulation& sim);

  const std::string& name() const { return name_; }
  const std::vector<std::string>& groups() const { return groups_; }  // the scene's body names
  const std::vector<char>& is_static() const { return static_; }      // per stepped body
  const std::vector<Solid>& solids() const { return solids_; }
  const std::vector<Joint>& joints() const { return joints_; }
  Eigen::Vector3d gravity() const { return gravity_; }
  double timestep() const { return timestep_; }
  int steps() const { return steps_; }
  int bodies() const { return static_cast<int>(static_.size()); }
  int frames() const { return static_cast<int>(time_.size()); }
  double size() const { return size_; }  // the diagonal of the box around the bodies at the start (m)

  // Per frame (sizes: frames, 3 x bodies x frames, 4 x bodies x frames, frames + 1).
  const std::vector<float>& time() const { return time_; }
  const std::vector<float>& positions() const { return positions_; }
  // Unit quaternions w, x, y, z in units of 1/32767 (a 1e-4 rad rounding, which no eye sees).
  const std::vector<int16_t>& orientations() const { return orientations_; }
  // Since the previous frame: the largest translational constraint error (m) and the deepest
  // contact penetration (m), so that no step's peak is lost to the decimation.
  const std::vector<float>& separation() const { return separation_; }
  const std::vector<float>& penetration() const { return penetration_; }
  // Frame f's contacts are contacts()[6 k .. 6 k + 6) for k in [contact_start()[f], contact_start()[f + 1]):
  // the point (world, m) and the impulse the step applied to body b, or to body a when b is
  // static (world, N s: the push a static ground gives).
  const std::vector<uint32_t>& contact_start() const { return contact_start_; }
  const std::vector<float>& contacts() const { return contacts_; }

 private:
  void push_poses(const Mechanism& m);  // the bodies' poses as the next frame's
  void take_frame(const Simulation& sim);
  void halve();  // drops every other frame after the first and doubles the period

  RecordOptions options_;
  std::string name_;
  std::vector<std::string> groups_;
  std::vector<char> static_;
  std::vector<Solid> solids_;
  std::vector<Joint> joints_;
  Eigen::Vector3d gravity_;
  double timestep_ = 0, size_ = 0, period_ = 0, last_time_ = 0;
  int steps_ = 0;
  float pending_separation_ = 0, pending_penetration_ = 0;  // maxima since the last frame
  std::vector<float> time_, positions_, separation_, penetration_, contacts_;
  std::vector<int16_t> orientations_;
  std::vector<uint32_t> contact_start_{0};
};

}  // namespace ldlpgs::view
