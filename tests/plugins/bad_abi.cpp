// A plugin built against another plugin ABI: the loader must refuse it.
#include "model/cell_model.hpp"

extern "C" __attribute__((visibility("default"))) int fibrodem_abi_version() {
  return fibrodem::kPluginAbiVersion + 1000;
}
extern "C" __attribute__((visibility("default"))) fibrodem::CellModel* fibrodem_create_cell_model() {
  return nullptr;
}
