#!/usr/bin/env bash
# Size of each layer of the tree: source files and lines (tests, generated
# and third-party files left out), and the functions longer than 40 lines.
# Needs universal-ctags (Debian: universal-ctags) for the function lengths.
# Usage: tests/build/tree_stats.sh [LAYER_DIR...]   (from the repository root)
set -euo pipefail
cd "$(git rev-parse --show-toplevel)"
if [[ $# -eq 0 ]]; then
  set -- $(git ls-files '*.h' '*.cpp' | grep -v '^tests/\|^build' | xargs -n1 dirname |
           sed -E 's#/(include|src|backends)(/.*)?$##' | sort -u)
fi
printf '%-28s %6s %7s %9s\n' layer files lines 'fn>40'
for layer in "$@"; do
  files=$(git ls-files "$layer" | grep -E '\.(h|cpp)$' | grep -v '^tests/' || true)
  # A layer's sub-layers are counted on their own rows.
  for other in "$@"; do
    [[ $other != "$layer" && $other == "$layer"/* ]] && files=$(grep -v "^$other/" <<<"$files" || true)
  done
  [[ -z $files ]] && continue
  n=$(wc -l <<<"$files")
  lines=$(cat $files | wc -l)
  long=$(ctags -x --_xformat='%{line} %{end}' --kinds-c++=f --languages=C++ $files 2>/dev/null |
         awk '$2-$1+1>40' | wc -l)
  printf '%-28s %6d %7d %9d\n' "$layer" "$n" "$lines" "$long"
done
