// The one place the viewer reads hapsim.v1.Frame: everything but the mesh
// into a ViewerFrame, the mesh part (keyframe, or topology edits and moved
// vertices) into a MeshCache.
#pragma once
#include <string>

#include "hapsim/v1/viewer.pb.h"
#include "hapsim/viewer/mesh_cache.h"
#include "hapsim/viewer/viewer_frame.h"

namespace hapsim::viewer {

// Decodes everything but the mesh into *out, reusing its storage. Event
// layers are named from the frame's own keyframe, else from `mesh` (the
// names come with the keyframe and a delta never changes them), so this may
// run before or after the frame's mesh is applied.
void DecodeFrame(const hapsim::v1::Frame& wire, const MeshCache& mesh, ViewerFrame* out);

// Decodes a stream's frames in order and keeps the mesh they lead to.
class FrameDecoder {
 public:
  // The frame's own content. Decoded whether or not its mesh applies: the
  // events of a frame the cache refuses still happened.
  const ViewerFrame& Decode(const hapsim::v1::Frame& wire);
  // Anything but kApplied leaves mesh() as it was (see MeshCache::Apply).
  ApplyResult ApplyMesh(const hapsim::v1::Frame& wire, std::string* why = nullptr) { return mesh_.Apply(wire, why); }
  // Forget the mesh (a new stream): the next frame must be a keyframe.
  void ForgetMesh() { mesh_.Invalidate(); }

  const ViewerFrame& frame() const { return frame_; }
  const MeshCache& mesh() const { return mesh_; }

 private:
  MeshCache mesh_;
  ViewerFrame frame_;
};

}  // namespace hapsim::viewer
