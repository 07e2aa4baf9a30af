#!/usr/bin/env bash
# Writes a class config for hapsim-server --class-config with fresh tokens:
#   DIR/class.toml                       the config (token hashes only, no secrets)
#   DIR/tokens/instructor.token          the instructor's token
#   DIR/tokens/observer.token            an observer's token
#   DIR/tokens/traineeK.token            trainee K's token (drives and views session tK only)
# Hand each person their token file; they pass it with --token-file.
#
# usage: deploy/make-class.sh DIR CLASS TRAINEES [SCENE [TARGET_DEPTH_MM]]
#   e.g. deploy/make-class.sh /tmp/class acu-101 8 acupuncture 10
#   TARGET_DEPTH_MM: the needle depth the trials' depth error is measured against
set -euo pipefail
if [ $# -lt 3 ] || [ "$1" = "-h" ] || [ "$1" = "--help" ]; then
  sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'
  [ $# -ge 1 ] && [ "$1" != "-h" ] && [ "$1" != "--help" ] && exit 2 || exit 0
fi
dir=$1 class=$2 trainees=$3 scene=${4:-acupuncture} target_depth_mm=${5:-}
[ -z "$target_depth_mm" ] || [[ $target_depth_mm =~ ^[0-9]+(\.[0-9]+)?$ ]] \
  || { echo "make-class: TARGET_DEPTH_MM must be a positive number" >&2; exit 2; }
[[ $class =~ ^[A-Za-z0-9_-]{1,63}$ ]] || { echo "make-class: class name must be 1-63 of [A-Za-z0-9_-]" >&2; exit 2; }
[[ $trainees =~ ^[0-9]+$ ]] && [ "$trainees" -ge 1 ] && [ "$trainees" -le 60 ] \
  || { echo "make-class: TRAINEES must be 1..60" >&2; exit 2; }
command -v openssl >/dev/null || { echo "make-class: openssl not found" >&2; exit 1; }
mkdir -p "$dir/tokens"
chmod 700 "$dir/tokens"
new_token() {  # name -> writes the token file, prints its sha256
  local t
  t=$(openssl rand -hex 24)
  (umask 077; printf '%s\n' "$t" > "$dir/tokens/$1.token")
  printf '%s' "$t" | openssl dgst -sha256 -r | cut -d' ' -f1
}
{
  echo "# hapsim class config written by deploy/make-class.sh on $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "# Tokens are in $dir/tokens/ (only their SHA-256 is here). Format: docs/classroom.md"
  echo
  echo "[[class]]"
  echo "name = \"$class\""
  [ -z "$target_depth_mm" ] || echo "target_depth_m = $(awk -v d="$target_depth_mm" 'BEGIN { printf "%.6f", d / 1000 }')"
  for k in $(seq 1 "$trainees"); do
    echo
    echo "[[class.session]]"
    echo "id = \"t$k\""
    echo "scene = \"$scene\""
    echo "trainee = \"trainee$k\""
  done
  echo
  echo "[[token]]"
  echo "name = \"instructor\""
  echo "role = \"instructor\""
  echo "class = \"$class\""
  echo "sha256 = \"$(new_token instructor)\""
  echo
  echo "[[token]]"
  echo "name = \"observer\""
  echo "role = \"observer\""
  echo "class = \"$class\""
  echo "sha256 = \"$(new_token observer)\""
  for k in $(seq 1 "$trainees"); do
    echo
    echo "[[token]]"
    echo "name = \"trainee$k\""
    echo "role = \"trainee\""
    echo "class = \"$class\""
    echo "sessions = [\"t$k\"]"
    echo "sha256 = \"$(new_token "trainee$k")\""
  done
} > "$dir/class.toml"
echo "make-class: wrote $dir/class.toml (class $class, sessions t1..t$trainees, scene $scene) and $((trainees + 2)) tokens in $dir/tokens/"
