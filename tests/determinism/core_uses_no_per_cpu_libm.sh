#!/usr/bin/env bash
# The core's object code must not call a C-library function whose last bits
# depend on the CPU (glibc chooses FMA/AVX2 or SSE2 variants of sin, exp,
# pow, ... at load time). Every such call belongs in portable_math.cpp's own
# implementations. Reads the undefined symbols of the static library, so it
# also catches calls made from inlined Eigen or standard-library code.
# Usage: core_uses_no_per_cpu_libm.sh LIBHAPSIM_CORE.a
set -euo pipefail
lib=${1:?usage: $0 LIBHAPSIM_CORE.a}
[ -f "$lib" ] || { echo "no such library: $lib" >&2; exit 2; }
# Transcendental functions (double, float and long double names). Exact
# operations (sqrt, fabs, floor, nearbyint, ldexp, frexp, fmod, remquo, fma)
# round the same everywhere and are allowed.
forbidden='^(sin|cos|tan|sincos|asin|acos|atan|atan2|sinh|cosh|tanh|asinh|acosh|atanh|exp|exp2|exp10|expm1|log|log2|log10|log1p|logb|pow|cbrt|hypot|erf|erfc|tgamma|lgamma|lgamma_r)[fl]?(@.*)?$'
found=$(nm -u --format=posix "$lib" 2>/dev/null | awk '{print $1}' | sed 's/^__\(.*\)_finite$/\1/' | grep -E "$forbidden" | sort -u || true)
if [ -n "$found" ]; then
  echo "FAIL: $lib calls C-library math that differs per CPU:" >&2
  echo "$found" | sed 's/^/  /' >&2
  for sym in $found; do
    nm -A -u "$lib" 2>/dev/null | grep -w "$sym" | sed 's/^/    in /' >&2
  done
  echo "use hapsim/core/math/portable_math.h instead" >&2
  exit 1
fi
echo "ok: $(nm -u --format=posix "$lib" | wc -l) undefined symbols in $(basename "$lib"), none from the per-CPU libm set"
