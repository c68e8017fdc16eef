// A shared library with the ABI version but no factory: the loader must name
// the missing entry point.
#include "model/cell_model.hpp"

extern "C" __attribute__((visibility("default"))) int fibrodem_abi_version() {
  return fibrodem::kPluginAbiVersion;
}
