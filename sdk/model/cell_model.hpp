// The plugin contract between the fibrodem core and a cell model.
//
// A cell model (ionic or myofilament) describes itself with a ModelInfo (states,
// parameters, inputs, outputs, variants, all with units) and evaluates a whole
// block of cells [begin, end) per call on structure-of-arrays storage, in the
// style of openCARP's LIMPET: one virtual call per block, none per cell.
//
// Every state's derivative is returned in the linear form
//     dy/dt = a + b * y
// For a gating variable b = -1/tau and a = y_inf/tau (or a = alpha,
// b = -(alpha + beta)), so Rush-Larsen can integrate it exactly over a step;
// for any other state b = 0 and a is the derivative itself.
//
// A model writes its equations once over a number type (block_access.hpp): the
// block is then evaluated in SIMD lanes of cells.
//
// These headers are all a plugin needs: header-only, they link nothing of the
// core (simd.hpp uses the header-only xsimd).
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace fibrodem {

// Bumped whenever anything in this header changes layout or meaning.
// (4: plugins also export the C++ standard library they were built with.)
inline constexpr int kPluginAbiVersion = 4;

// The C++ standard library and its ABI this code is compiled against. ModelInfo
// holds std::string, std::vector and std::map, whose layout differs between
// libstdc++'s old and new (C++11) string ABI and libc++: a plugin and a core
// that disagree here read each other's metadata as garbage (std::bad_alloc), so
// the loader compares the plugin's value with its own.
#if defined(_LIBCPP_VERSION)
#define FIBRODEM_STRINGIFY_(x) #x
#define FIBRODEM_STRINGIFY(x) FIBRODEM_STRINGIFY_(x)
inline constexpr const char* kStdlibAbi = "libc++ (ABI " FIBRODEM_STRINGIFY(_LIBCPP_ABI_VERSION) ")";
#elif defined(__GLIBCXX__)
#if _GLIBCXX_USE_CXX11_ABI
inline constexpr const char* kStdlibAbi = "libstdc++ (_GLIBCXX_USE_CXX11_ABI=1)";
#else
inline constexpr const char* kStdlibAbi = "libstdc++ (_GLIBCXX_USE_CXX11_ABI=0)";
#endif
#else
inline constexpr const char* kStdlibAbi = "unknown C++ standard library";
#endif

enum class ModelKind { ionic, myofilament };

struct StateInfo {
  std::string name;
  std::string unit;
  double initial = 0.0;
  // Physical range; leaving it is a blow-up and stops the run (naming the state).
  double lower = -1e300;
  double upper = 1e300;
  // Gating variable: integrated exactly by Rush-Larsen from its linear form.
  bool gate = false;
  // A gate whose a and b depend only on V (and the parameters): the core may
  // tabulate them in V (solver.lookup_tables) and ask the model to skip them.
  bool voltage_only = false;
};

struct ParameterInfo {
  std::string name;
  std::string unit;
  double default_value = 0.0;
  std::string description;
};

// A named parameter set of a model (Myokit style: a variant is a parameter
// change, not a copy). It may also replace initial state values.
struct VariantInfo {
  std::string name;
  std::string description;
  std::map<std::string, double> parameters;
  std::map<std::string, double> initial_state;
};

// An input or output signal of a model: `i_ext` (whole-cell pA, positive =
// depolarising) for ionic models, `Ca_i` (mM), `stretch` (1), ...
struct SignalInfo {
  std::string name;
  std::string unit;
  std::string description;
};

struct ModelInfo {
  std::string name;
  std::string version;
  std::string description;
  std::string reference;  // the paper(s) the equations come from
  ModelKind kind = ModelKind::ionic;
  std::vector<StateInfo> states;
  std::vector<ParameterInfo> parameters;
  std::vector<SignalInfo> inputs;
  std::vector<SignalInfo> outputs;
  std::vector<VariantInfo> variants;  // the first one is the default, if any
  // Index of the membrane potential among the states (ionic models).
  int voltage_state = -1;
  // Membrane capacitance is a parameter of the model; its index (ionic models).
  int capacitance_parameter = -1;
};

// Views of one block of cells in structure-of-arrays layout. Array X of
// quantity k for cell c is X[k * stride + c] (a and b: X[k * ab_stride + c]). Parameters are shared by the
// block (one value each).
struct BlockView {
  std::size_t begin = 0;
  std::size_t end = 0;
  std::size_t stride = 0;
  const double* y = nullptr;       // states     [n_states  * stride]
  const double* params = nullptr;  // parameters [n_params]
  const double* inputs = nullptr;  // inputs     [n_inputs  * stride]
  double* a = nullptr;             // dy/dt = a + b*y   [n_states * ab_stride]
  double* b = nullptr;             //                   [n_states * ab_stride]
  double* outputs = nullptr;       // outputs    [n_outputs * stride], may be null
  // Stride of a and b, which may live in a small scratch tile of the block's
  // cells while y lives in the population (0: the same as stride).
  std::size_t ab_stride = 0;
  // When true the model may leave a, b of its voltage_only gates unwritten: the
  // core fills them from its lookup table (it never sets this for a model
  // without voltage_only gates). Everything else must still be written.
  bool skip_voltage_only_gates = false;
  // The scalar reference path (solver.simd false): evaluate one cell at a time
  // in double instead of in SIMD lanes (block_access.hpp does this for a model
  // written over its number type). The two differ by round-off only.
  bool scalar_reference = false;
};

class CellModel {
 public:
  virtual ~CellModel() = default;
  virtual const ModelInfo& info() const = 0;
  // Fill a, b (and outputs if non-null) for cells [begin, end) at time t_ms.
  // Must not allocate, throw or keep state: the same call may come from several
  // threads on disjoint blocks.
  virtual void evaluate(const BlockView& block, double t_ms) const = 0;
};

}  // namespace fibrodem

// Each plugin library defines exactly one model with this macro.
#define FIBRODEM_CELL_MODEL_PLUGIN(ModelClass)                                  \
  extern "C" __attribute__((visibility("default"))) int fibrodem_abi_version() { \
    return ::fibrodem::kPluginAbiVersion;                                       \
  }                                                                             \
  extern "C" __attribute__((visibility("default"))) const char*                 \
  fibrodem_stdlib_abi() {                                                       \
    return ::fibrodem::kStdlibAbi;                                              \
  }                                                                             \
  extern "C" __attribute__((visibility("default")))                             \
  ::fibrodem::CellModel* fibrodem_create_cell_model() {                         \
    return new ModelClass();                                                    \
  }
