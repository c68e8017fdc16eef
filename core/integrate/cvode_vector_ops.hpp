// CVODE's vector operations for N_Vector_Serial, compiled with the project.
//
// Debian 12's libsundials-dev is built without optimisation: each of its
// serial vector operations keeps its loop counter in memory, and on one cell
// (21-31 states) CVODE's own vector arithmetic took more CPU than the cell
// model. These compute each entry by the same expression, in the same order,
// as SUNDIALS 6's nvector_serial (including its special cases, such as
// c (x + y) when a == b in N_VLinearSum), and are compiled without
// contracting a * x + b * y into fused multiply-adds, so a run's numbers are
// bit for bit those of the library's operations.
#pragma once

#include <nvector/nvector_serial.h>

namespace fibrodem {

// Replaces the operations of `v` (a serial N_Vector); clones of it, which
// CVODE makes of its state vector for all its work vectors, copy them.
void use_compiled_vector_ops(N_Vector v);

}  // namespace fibrodem
