// hapsim's DDS topics (types: proto/dds/haptics.idl, generated as
// hapsim::dds_types). Every endpoint of a topic lives in a session's
// partition (partition.h).
#pragma once
#include "hapsim/dds/dds.h"
#include "haptics.h"

namespace hapsim::dds {

inline constexpr const char* kPoseTopic = "hapsim_StylusPose";        // bridge -> server, 1 kHz
inline constexpr const char* kModelTopic = "hapsim_LocalForceModel";  // server -> bridge, per tick

using PoseWriter = Writer<hapsim_dds_StylusPose>;
using PoseReader = Reader<hapsim_dds_StylusPose>;
using ModelWriter = Writer<hapsim_dds_LocalForceModel>;
using ModelReader = Reader<hapsim_dds_LocalForceModel>;

}  // namespace hapsim::dds
