# Shared by the network-lab tests, after lib.sh: sets $repo and $netlab,
# points the lab at this test's work directory, exits 77 (skipped) where
# namespaces cannot be made, and removes the lab on exit. Then:
#   lab_up NAME [netlab.sh up flags and hosts]   -> sets $lab (NAME + this shell's pid)
#   on_bg HOST CMD...                            -> CMD on HOST in the background; $! is CMD itself
repo=$(cd "$here/../.." && pwd)
netlab="$repo/netlab/netlab.sh"
export HAPSIM_LINKEM="$bin/hapsim-linkem" HAPSIM_NETLAB_STATE="$work/state"
"$netlab" check || exit 77
lab_up() {
  lab=$1$$; shift
  trap 'cleanup; "$netlab" down $lab >/dev/null 2>&1 || true' EXIT
  "$netlab" up "$lab" --owner $$ "$@"
}
# netlab.sh and ip exec into the process, so $! is the command itself.
on_bg() { "$netlab" exec "$lab" "$@" & }
