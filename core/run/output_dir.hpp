// The output folder is checked before any computation: it can be created, it can be written, and it does not hold another
// run's files (summary.json) unless overwriting was asked for. Each problem
// is a ManifestError naming the folder and the reason.
#pragma once

#include <filesystem>

namespace fibrodem {

void prepare_output_dir(const std::filesystem::path& dir, bool overwrite);

}  // namespace fibrodem
