// Compiled with -ffp-contract=off (core/CMakeLists.txt): see the header.
#include "integrate/cvode_vector_ops.hpp"

#include <cmath>

namespace fibrodem {

namespace {

// to += c from, as the library's axpy (c = 1 and -1 without the product).
void axpy(double c, const double* from, double* to, sunindextype n) {
  if (c == 1.0)
    for (sunindextype i = 0; i < n; ++i) to[i] += from[i];
  else if (c == -1.0)
    for (sunindextype i = 0; i < n; ++i) to[i] -= from[i];
  else
    for (sunindextype i = 0; i < n; ++i) to[i] += c * from[i];
}

// z = a x + b y, by the case the library picks for a and b.
void linear_sum(double a, N_Vector x, double b, N_Vector y, N_Vector z) {
  const sunindextype n = NV_LENGTH_S(x);
  double* xd = NV_DATA_S(x);
  double* yd = NV_DATA_S(y);
  double* zd = NV_DATA_S(z);
  // y <- y + a x (b == 1, z is y) or x <- x + b y (a == 1, z is x).
  if (b == 1.0 && z == y) return axpy(a, xd, yd, n);
  if (a == 1.0 && z == x) return axpy(b, yd, xd, n);
  if (a == 1.0 && b == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] + yd[i];
  } else if (a == 1.0 && b == -1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] - yd[i];
  } else if (a == -1.0 && b == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = yd[i] - xd[i];
  } else if (a == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = (b * yd[i]) + xd[i];
  } else if (b == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = (a * xd[i]) + yd[i];
  } else if (a == -1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = (b * yd[i]) - xd[i];
  } else if (b == -1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = (a * xd[i]) - yd[i];
  } else if (a == b) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * (xd[i] + yd[i]);
  } else if (a == -b) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * (xd[i] - yd[i]);
  } else {
    for (sunindextype i = 0; i < n; ++i) zd[i] = (a * xd[i]) + (b * yd[i]);
  }
}

void constant(double c, N_Vector z) {
  const sunindextype n = NV_LENGTH_S(z);
  double* zd = NV_DATA_S(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = c;
}

void product(N_Vector x, N_Vector y, N_Vector z) {
  const sunindextype n = NV_LENGTH_S(x);
  double* xd = NV_DATA_S(x);
  const double* yd = NV_DATA_S(y);
  double* zd = NV_DATA_S(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] * yd[i];
}

void quotient(N_Vector x, N_Vector y, N_Vector z) {
  const sunindextype n = NV_LENGTH_S(x);
  double* xd = NV_DATA_S(x);
  const double* yd = NV_DATA_S(y);
  double* zd = NV_DATA_S(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] / yd[i];
}

void scale(double c, N_Vector x, N_Vector z) {
  const sunindextype n = NV_LENGTH_S(x);
  double* xd = NV_DATA_S(x);
  double* zd = NV_DATA_S(z);
  if (z == x) {
    for (sunindextype i = 0; i < n; ++i) xd[i] *= c;
  } else if (c == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i];
  } else if (c == -1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = -xd[i];
  } else {
    for (sunindextype i = 0; i < n; ++i) zd[i] = c * xd[i];
  }
}

void absolute(N_Vector x, N_Vector z) {
  const sunindextype n = NV_LENGTH_S(x);
  double* xd = NV_DATA_S(x);
  double* zd = NV_DATA_S(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = std::fabs(xd[i]);
}

void inverse(N_Vector x, N_Vector z) {
  const sunindextype n = NV_LENGTH_S(x);
  double* xd = NV_DATA_S(x);
  double* zd = NV_DATA_S(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = 1.0 / xd[i];
}

void add_constant(N_Vector x, double b, N_Vector z) {
  const sunindextype n = NV_LENGTH_S(x);
  double* xd = NV_DATA_S(x);
  double* zd = NV_DATA_S(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] + b;
}

double dot_product(N_Vector x, N_Vector y) {
  const sunindextype n = NV_LENGTH_S(x);
  double* xd = NV_DATA_S(x);
  const double* yd = NV_DATA_S(y);
  double sum = 0.0;
  for (sunindextype i = 0; i < n; ++i) sum += xd[i] * yd[i];
  return sum;
}

double max_norm(N_Vector x) {
  const sunindextype n = NV_LENGTH_S(x);
  double* xd = NV_DATA_S(x);
  double max = 0.0;
  for (sunindextype i = 0; i < n; ++i)
    if (std::fabs(xd[i]) > max) max = std::fabs(xd[i]);
  return max;
}

double weighted_square_sum(N_Vector x, N_Vector w) {
  const sunindextype n = NV_LENGTH_S(x);
  double* xd = NV_DATA_S(x);
  const double* wd = NV_DATA_S(w);
  double sum = 0.0;
  for (sunindextype i = 0; i < n; ++i) {
    const double p = xd[i] * wd[i];
    sum += p * p;
  }
  return sum;
}

double wrms_norm(N_Vector x, N_Vector w) {
  return std::sqrt(weighted_square_sum(x, w) / static_cast<double>(NV_LENGTH_S(x)));
}

double minimum(N_Vector x) {
  const sunindextype n = NV_LENGTH_S(x);
  double* xd = NV_DATA_S(x);
  double min = xd[0];
  for (sunindextype i = 1; i < n; ++i)
    if (xd[i] < min) min = xd[i];
  return min;
}

void compare(double c, N_Vector x, N_Vector z) {
  const sunindextype n = NV_LENGTH_S(x);
  double* xd = NV_DATA_S(x);
  double* zd = NV_DATA_S(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = std::fabs(xd[i]) >= c ? 1.0 : 0.0;
}

sunbooleantype inverse_test(N_Vector x, N_Vector z) {
  const sunindextype n = NV_LENGTH_S(x);
  double* xd = NV_DATA_S(x);
  double* zd = NV_DATA_S(z);
  sunbooleantype no_zero = SUNTRUE;
  for (sunindextype i = 0; i < n; ++i) {
    if (xd[i] == 0.0)
      no_zero = SUNFALSE;
    else
      zd[i] = 1.0 / xd[i];
  }
  return no_zero;
}

}  // namespace

void use_compiled_vector_ops(N_Vector v) {
  N_Vector_Ops ops = v->ops;
  ops->nvlinearsum = linear_sum;
  ops->nvconst = constant;
  ops->nvprod = product;
  ops->nvdiv = quotient;
  ops->nvscale = scale;
  ops->nvabs = absolute;
  ops->nvinv = inverse;
  ops->nvaddconst = add_constant;
  ops->nvdotprod = dot_product;
  ops->nvmaxnorm = max_norm;
  ops->nvwrmsnorm = wrms_norm;
  ops->nvwsqrsumlocal = weighted_square_sum;
  ops->nvmin = minimum;
  ops->nvcompare = compare;
  ops->nvinvtest = inverse_test;
}

}  // namespace fibrodem
