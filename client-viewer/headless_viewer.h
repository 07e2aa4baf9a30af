// hapsim-viewer --headless without pictures: keeps the mesh current from the
// stream until a limit or SIGINT/SIGTERM, then prints the stream's counts and
// what happened to the tissue and writes the final mesh.
#pragma once
#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

#include "hapsim/viewer/viewer_client.h"

namespace hapsim::viewer {

struct HeadlessOutputs {
  std::string record_path;  // the frame stream, as received ("" none)
  std::string obj_path;     // the final mesh as OBJ ("" none)
  std::string export_path;  // the final mesh by extension: .obj .gltf .glb .vtk ("" none)
};

// The process exit code: 0, or 1 when a file cannot be written or the
// stream ended for another reason than a limit or a signal.
int RunHeadlessViewer(std::shared_ptr<grpc::Channel> channel, ViewerOptions options, const HeadlessOutputs& outputs);

}  // namespace hapsim::viewer
