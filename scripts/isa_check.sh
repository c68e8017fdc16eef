#!/usr/bin/env bash
# The plugin SDK compiles at every optimisation level on every x86-64 level:
# compile only (nothing runs, so a host without AVX-512 checks AVX-512 too)
#   - the SDK headers, with every lane function of simd.hpp instantiated for
#     SIMD lanes and for double (xsimd's log and pow among them),
#   - the smallest cell-model plugin (plugins/passive_fibroblast),
#   - the smallest contact-law plugin (plugins/linear_bond),
# at -O0 (a Debug build or a bare compiler line) and -O2 (Release), for
# -march=x86-64 (SSE2), x86-64-v2 (SSE4.2), x86-64-v3 (AVX2, FMA) and
# x86-64-v4 (AVX-512). The plugins see only the SDK's headers, staged as the
# install ships them; xsimd comes from the compiler's include path.
#   scripts/isa_check.sh        (CXX=clang++ for another compiler;
#                                ISA_CHECK_JOBS=N parallel compiles, default 2)
# 24 compiles, 28 s of CPU in all: ~15 s on 2 idle cores (95-120 s measured
# with the machine loaded 7-fold by other jobs).
set -euo pipefail
cd "$(dirname "$0")/.."
cxx=${CXX:-c++}
jobs=${ISA_CHECK_JOBS:-2}
work=$(mktemp -d "${TMPDIR:-/tmp}/fibrodem_isa.XXXXXX")
trap 'rm -rf "$work"' EXIT

# The SDK's headers, as cmake/FibrodemSdk.cmake lists them.
sdk_headers=$(sed -n '/^set(FIBRODEM_SDK_HEADERS/,/)/p' cmake/FibrodemSdk.cmake |
              grep -oE '[a-z_]+/[a-z_]+\.hpp')
[ -n "$sdk_headers" ] || { echo "isa_check: no SDK headers found in cmake/FibrodemSdk.cmake" >&2; exit 1; }
for header in $sdk_headers; do
  mkdir -p "$work/include/$(dirname "$header")"
  cp "sdk/$header" "$work/include/$header"
done

{
  for header in $sdk_headers; do echo "#include \"$header\""; done
  cat <<'CPP'
namespace {
FIBRODEM_USE_LANE_MATH;
template <class R>
R every_lane_function(const R& x, const R& y) {
  const R sum = exp(x) + expm1(x) + log(x) + sqrt(x) + fabs(x) + pow(x, 2.5) + pow(x, y) + pow(2.5, y) +
                fmin(x, y) + fmax(x, y) + floor(x) + exprel(x);
  return select(x < y, sum, 1.0) + select(x > y, 2.0, sum) + select(x == y, 1.0, 2.0);
}
}  // namespace
// Exported, so that -O2 compiles them in full.
fibrodem::simd::Real isa_check_lanes(const double* x, const double* y, std::size_t n) {
  return every_lane_function(fibrodem::simd::load(x, n), fibrodem::simd::load(y, n));
}
double isa_check_scalar(double x, double y) { return every_lane_function(x, y); }
CPP
} > "$work/sdk_headers.cpp"

# Each check: source, then its own flags (as its CMakeLists.txt gives them).
checks=(
  "$work/sdk_headers.cpp|"
  "plugins/passive_fibroblast/passive_fibroblast.cpp|"
  "plugins/linear_bond/linear_bond.cpp|-Iplugins -fno-math-errno -fno-trapping-math -fopenmp-simd"
)
common=(-std=c++20 -fPIC -fvisibility=hidden -Wall -Wextra -I"$work/include")
# As the SDK's CMake package adds them for GCC 12 (GCC bug 105593).
if [ "$(echo __GNUC__ __clang__ | "$cxx" -E -P -x c++ - | xargs)" = "12 __clang__" ]; then
  common+=(-Wno-uninitialized -Wno-maybe-uninitialized)
fi

compile() {  # ARCH OPT SOURCE EXTRA_FLAGS LOG
  # shellcheck disable=SC2086
  "$cxx" "${common[@]}" "-march=$1" "$2" $4 -c "$3" -o /dev/null >"$5" 2>&1
}

started=$SECONDS
n=0
running=0
for arch in x86-64 x86-64-v2 x86-64-v3 x86-64-v4; do
  for opt in -O0 -O2; do
    for check in "${checks[@]}"; do
      n=$((n + 1))
      source=${check%%|*}
      echo "$(basename "$source") at $opt -march=$arch" >"$work/what.$n"
      ( compile "$arch" "$opt" "$source" "${check#*|}" "$work/log.$n" && touch "$work/ok.$n" ) &
      running=$((running + 1))
      if [ "$running" -ge "$jobs" ]; then wait -n || true; running=$((running - 1)); fi
    done
  done
done
wait

failed=0
for i in $(seq 1 "$n"); do
  if [ ! -f "$work/ok.$i" ]; then
    failed=$((failed + 1))
    echo "isa_check: FAILED to compile $(cat "$work/what.$i") with $("$cxx" --version | head -1):" >&2
    head -n 25 "$work/log.$i" >&2
  fi
done
if [ "$failed" -gt 0 ]; then
  echo "isa_check: $failed of $n compiles failed (above)" >&2
  exit 1
fi
echo "isa_check: passed ($n compiles: SDK headers, passive_fibroblast, linear_bond at -O0 and -O2 for" \
     "x86-64, x86-64-v2, x86-64-v3, x86-64-v4; $((SECONDS - started)) s)"
