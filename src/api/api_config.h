#pragma once
// The public API's configuration (include/esdslam/esdslam.h, SystemConfig) resolved into the
// one run configuration (system/run_config.h), the same way `esdslam run` resolves its settings
// file and flags; and the conversions between the public and the internal types.

#include "esdslam/esdslam.h"
#include "system/run_config.h"

namespace esdslam {

// Loads the settings (file or text), applies the config as run flags; label_input makes the
// semantic stage take each frame's labels (Semantic.segmenter: provided, every frame, the
// config's class table). Throws Error naming the file and key.
RunConfig ResolveApiConfig(const SystemConfig& config);

Matrix4 ToMatrix4(const Rigid3& transform);
TrackingStatus ToStatus(TrackingState state);

}  // namespace esdslam
