// The one error of the CellML importer: what could not be translated and where
// (the element's path in the document, with its line).
#pragma once

#include <stdexcept>
#include <string>

namespace fibrodem::cellml {

class ImportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace fibrodem::cellml
