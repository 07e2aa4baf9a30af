// One frame of a session's stream as the viewer uses it: decoded once from
// the wire (FrameDecoder) and read by every consumer — the headless
// summary, the window's scene, a replay. The mesh is not in it: the frame's
// mesh part goes into the MeshCache, which holds the mesh it leads to.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "hapsim/viewer/event_kind.h"

namespace hapsim::viewer {

struct FrameTool {
  bool valid = false;  // the frame carries a tool pose (a device streams)
  Eigen::Vector3d tip_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // unit; tool +z from the tip to the handle
  // Of the tissue on the tool, with or without a pose (none streams: the scene's, 0).
  Eigen::Vector3d force_N = Eigen::Vector3d::Zero();
  std::string contact_state;  // free | contact | punctured | cutting ("" from a frame without one)
};

struct FrameEvent {
  double t_s = 0.0;  // sim time
  EventKind kind = EventKind::kUnknown;
  int layer_index = -1;  // into the keyframe's layer names, -1 none
  std::string layer;     // that layer's name, "" when none or out of range
  bool has_where = false;
  Eigen::Vector3d where_m = Eigen::Vector3d::Zero();  // where it happened (a puncture: the tip)
  double value = 0.0;                                 // kCutEnd: the incision's length [m]
};

struct ViewerFrame {
  std::uint64_t seq = 0;  // contiguous per stream, 0 for the stream's keyframe
  std::uint64_t topology_version = 0;
  double sim_time_s = 0.0;
  bool paused = false;
  bool keyframe = false;           // replaces the whole mesh
  bool topology_edits = false;     // a delta with topology edits (a cut): the triangle list changes
  std::size_t moved_vertices = 0;  // vertices a delta moves
  FrameTool tool;
  int current_layer = -1;    // the layer the tip is in or touches, -1 none
  double tip_depth_m = 0.0;  // below the top surface
  // The peak |force on the tool| over the 1 kHz ticks since the previous
  // frame — what a force plot at the frame rate shows; never below the
  // frame's own force (all a server without the field sends).
  double peak_force_N = 0.0;
  std::vector<FrameEvent> events;  // since the previous frame of this stream, in order
};

}  // namespace hapsim::viewer
