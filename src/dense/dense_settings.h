#pragma once
// Dense.* settings keys.

#include "dense/dense_options.h"
#include "io/settings_table.h"

namespace esdslam {

void BindDenseSettings(DenseOptions& options, SettingsTable& table);

}  // namespace esdslam
