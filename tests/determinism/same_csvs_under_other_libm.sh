#!/usr/bin/env bash
# Runs one validation again with glibc's other math code paths
# (GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA: what a CPU without AVX2/FMA
# gets) and requires every CSV to be byte-identical to the ordinary run's.
# CSVs of wall-clock timings are named with --skip and left out.
# Usage: same_csvs_under_other_libm.sh HAPSIM_VALIDATE NAME REF_DIR OUT_DIR [--skip FILE.csv]...
set -euo pipefail
validate=$1 name=$2 ref=$3 out=$4
shift 4
skip=()
while [ $# -gt 0 ]; do
  [ "$1" = --skip ] && [ $# -ge 2 ] || { echo "usage: $0 VALIDATE NAME REF OUT [--skip F]..." >&2; exit 2; }
  skip+=("$2")
  shift 2
done
rm -rf "$out"
GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA "$validate" "$name" --out "$out" >/dev/null
compared=0 differ=0
for f in "$ref"/*.csv; do
  base=$(basename "$f")
  for s in "${skip[@]:-}"; do [ "$base" = "$s" ] && continue 2; done
  [ -f "$out/$base" ] || { echo "FAIL: $base missing from the run under other libm paths" >&2; differ=$((differ + 1)); continue; }
  if ! cmp -s "$f" "$out/$base"; then
    echo "FAIL: $base differs under GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA; first differing lines:" >&2
    diff "$f" "$out/$base" | head -6 >&2 || true
    differ=$((differ + 1))
  fi
  compared=$((compared + 1))
done
[ "$compared" -gt 0 ] || { echo "FAIL: no CSV in $ref to compare" >&2; exit 1; }
echo "$name: $compared CSVs compared, $differ differ${skip[*]:+ (timings skipped: ${skip[*]})}"
[ "$differ" -eq 0 ]
