#include "run/output_dir.hpp"

#include <fstream>
#include <system_error>

#include "util/manifest_error.hpp"

namespace fibrodem {

namespace fs = std::filesystem;

void prepare_output_dir(const fs::path& dir, bool overwrite) {
  const std::string where = "output.dir (" + dir.string() + ")";
  std::error_code error;
  fs::create_directories(dir, error);
  if (error || !fs::is_directory(dir))
    throw ManifestError(where, "cannot create the output folder: " +
                                   (error ? error.message() : std::string("a file of that name is in the way")));
  if (fs::exists(dir / "summary.json") && !overwrite)
    throw ManifestError(where, "holds another run's files (summary.json): choose another folder (--out) or pass "
                               "--overwrite to replace them");
  // Can a file be written there? (Permissions, a read-only file system.)
  const fs::path probe = dir / ".fibrodem_write_test";
  {
    std::ofstream out(probe);
    out << "fibrodem";
    out.flush();
    if (!out) throw ManifestError(where, "cannot write into the output folder (permissions? a read-only disk?)");
  }
  fs::remove(probe, error);
}

}  // namespace fibrodem
