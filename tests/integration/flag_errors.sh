#!/usr/bin/env bash
# Bad command lines get exit code 2 and a message naming what is wrong,
# before anything starts or connects (docs/reliability.md, gaps 3, 5, 6, 9).
# Usage: flag_errors.sh BIN_DIR
set -uo pipefail
bin=${1:?usage: $0 BIN_DIR}
here=$(cd "$(dirname "$0")" && pwd)
failures=0
# expect CODE PATTERN COMMAND...: exit code CODE and stderr matching PATTERN.
expect() {
  local code=$1 pattern=$2; shift 2
  local err rc
  err=$("$@" 2>&1 >/dev/null); rc=$?
  if [ "$rc" -eq "$code" ] && grep -q -- "$pattern" <<<"$err"; then
    echo "ok   $* -> $rc: $(head -1 <<<"$err")"
  else
    echo "FAIL $* -> exit $rc (want $code), stderr: $err"; failures=$((failures + 1))
  fi
}
expect 2 "hapsim-ctl create: unknown flag --scen (see hapsim-ctl create --help)" "$bin/hapsim-ctl" \
    --server 127.0.0.1:9 create --scen cutting
expect 2 "hapsim-ctl list: unknown flag --id (see hapsim-ctl list --help)" "$bin/hapsim-ctl" --server 127.0.0.1:9 \
    list --id x
expect 2 "hapsim-ctl snapshot: flag --obj needs a value" "$bin/hapsim-ctl" --server 127.0.0.1:9 snapshot s1 --obj
expect 2 "hapsim-ctl list: takes no id, got 'x'" "$bin/hapsim-ctl" --server 127.0.0.1:9 list x
expect 2 "hapsim-ctl info: takes one id, got 'a' and 'b'" "$bin/hapsim-ctl" --server 127.0.0.1:9 info a b
expect 0 "usage: hapsim-ctl create \[ID\] \[flags\]" bash -c '"$0" create --help >&2' "$bin/hapsim-ctl"
expect 2 "give the id once (ID or --id), got 'a' and 'b'" "$bin/hapsim-ctl" --server 127.0.0.1:9 create a --id b
expect 2 "snapshot ID --obj FILE | --export FILE" "$bin/hapsim-ctl" --server 127.0.0.1:9 snapshot s1
expect 2 "--frame-rate-hz must be within (0, 1000]" "$bin/hapsim-server" --listen 127.0.0.1:0 --frame-rate-hz 0
expect 2 "--pose-timeout-ms must be within (0, 60000]" "$bin/hapsim-server" --listen 127.0.0.1:0 --pose-timeout-ms 1e18
expect 2 "--quantum-mm must be within (0, 1]" "$bin/hapsim-server" --listen 127.0.0.1:0 --quantum-mm 5
expect 2 "--rt-priority must be within \[0, 98\]" "$bin/hapsim-server" --listen 127.0.0.1:0 --rt-priority 99
expect 2 "--tick-cpus: \"0-\" is not a CPU list like 0, 0,2 or 2-3" "$bin/hapsim-server" --listen 127.0.0.1:0 --tick-cpus 0-
expect 2 "--tick-cpus: CPU 1000 is not one this process may run on" "$bin/hapsim-server" --listen 127.0.0.1:0 --tick-cpus 1000
expect 2 "--dds-io-scheduling: \"fast\" is neither batch nor normal" "$bin/hapsim-server" --listen 127.0.0.1:0 --dds-io-scheduling fast
expect 2 "--tick-wait: \"poll\" is neither sleep nor spin" "$bin/hapsim-server" --listen 127.0.0.1:0 --tick-wait poll
expect 2 "--tick-wait spin and --rt-priority exclude each other" "$bin/hapsim-server" --listen 127.0.0.1:0 --tick-wait spin --rt-priority 10
expect 2 "--clock-phase-spread must be within \[0, 1\]" "$bin/hapsim-load" --clock-phase-spread 2
expect 2 "--rt-priority must be within \[0, 98\]" "$bin/hapsim-bridge" --rt-priority 99
# Durations that would overflow when converted to ns or tick counts
# (docs/reliability.md, gap 6).
expect 2 "--seconds must be within \[0, 1e7\]" "$bin/hapsim-viewer" --session s --seconds 1e300
expect 2 "--connect-timeout-s must be within (0, 3600]" "$bin/hapsim-viewer" --session s --connect-timeout-s 1e16
expect 2 "--max-rate-hz must be within 0 or \[0.01, 1000\]" "$bin/hapsim-viewer" --session s --max-rate-hz 1e-12
# The viewer's picture flags: named before any window or connection.
if grep -q -- "--png" <<<"$("$bin/hapsim-viewer" --help)"; then
  expect 2 "--size wants WIDTHxHEIGHT" "$bin/hapsim-viewer" --session s --headless --png x.png --size 10x10
  expect 2 "--size wants WIDTHxHEIGHT" "$bin/hapsim-viewer" --session s --size 1280
  expect 2 "--max-triangles" "$bin/hapsim-viewer" --session s --max-triangles -5
  expect 2 "--camera wants TX,TY,TZ,DISTANCE,YAW,PITCH" "$bin/hapsim-viewer" --session s --camera 0,0,0,-1,0,0
  expect 2 "--camera wants TX,TY,TZ,DISTANCE,YAW,PITCH" "$bin/hapsim-viewer" --session s --camera 0,0,nan,1,0,0
  expect 2 "--benchmark-seconds must be within \[0, 3600\]" "$bin/hapsim-viewer" --session s --benchmark-seconds 1e9
  expect 2 "--class-rate-hz must be within \[0.1, 50\]" "$bin/hapsim-viewer" --class c --class-rate-hz 0
  expect 2 "--class is the window's instructor console" "$bin/hapsim-viewer" --class c --headless
  expect 1 "cannot read /nonexistent.frames" "$bin/hapsim-viewer" --headless --replay /nonexistent.frames --png x.png
  printf 'garbage!' >"${TMPDIR:-/tmp}/hapsim-garbage.frames"
  expect 1 "not a hapsim frame recording" "$bin/hapsim-viewer" --headless --replay "${TMPDIR:-/tmp}/hapsim-garbage.frames" --png x.png
  rm -f "${TMPDIR:-/tmp}/hapsim-garbage.frames"
  recording="$(cd "$(dirname "$0")/.." && pwd)/viewer-gui/data/acupuncture.frames"
  expect 1 "cannot write /nonexistent-dir/x.png" "$bin/hapsim-viewer" --headless --replay "$recording" --png /nonexistent-dir/x.png
  # No display: a clear message, not a crash.
  expect 1 "without a display use --headless, or ask for files" env -u DISPLAY -u WAYLAND_DISPLAY "$bin/hapsim-viewer" --session s
fi
expect 2 "--seconds must be within \[0, 1e7\]" "$bin/hapsim-bridge" --seconds 1e20
expect 2 "--seconds must be within \[0, 1e7\]" "$bin/hapsim-load" --seconds 1e20
expect 2 "hold time must be in \[0, 1e7\] s" "$bin/hapsim-bridge" --hold-s 1e300
# The same mistake gets the same exit code in the bridge and the load
# generator (docs/reliability.md, gap 9): bad script, bad safety setting, bad session id, bad params.
expect 2 "speed must be in (0, 1\] m/s" "$bin/hapsim-bridge" --speed-mm-s 0
expect 2 "speed must be in (0, 1\] m/s" "$bin/hapsim-load" --speed-mm-s 0
expect 2 "force" "$bin/hapsim-bridge" --max-force-n -1
expect 2 "force" "$bin/hapsim-load" --max-force-n -1
expect 2 "--session must be within \[A-Za-z0-9_-\]{1,63}" "$bin/hapsim-bridge" --session "a b"
expect 2 "is not \[A-Za-z0-9_-\]{1,63}" "$bin/hapsim-load" --sessions "a b"
expect 2 "--params wants KEY=NUMBER" "$bin/hapsim-load" --create tissue_block --params stiffness
expect 2 "unknown backend 'phantom'" "$bin/hapsim-bridge" --backend phantom
# Several devices: each --device names a valid, distinct session; the OpenHaptics flags are checked before any device opens.
expect 2 "--device 'a b': the session must be" "$bin/hapsim-bridge" --device "a b"
expect 2 "--device: session 't1' twice" "$bin/hapsim-bridge" --device t1 --device t1:Left
expect 2 "--workspace-scale must be in (0, 100\]" "$bin/hapsim-bridge" --backend openhaptics --workspace-scale 0
expect 2 "--arm-button must be 0 (none) or 1-4" "$bin/hapsim-bridge" --arm-button 9
# A missing OpenHaptics runtime is a runtime error naming the library.
expect 1 "cannot load the OpenHaptics HD library '/nonexistent/libHD.so'" "$bin/hapsim-bridge" --backend openhaptics \
    --hd-library /nonexistent/libHD.so
# Classroom: a broken class config or TLS setup stops the server at
# start, naming the file and place; clients name unreadable token/TLS files.
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
printf '[[class]]\nname = "c"\n[[class.session]]\nid = "t1"\ncolour = "red"\n' >"$tmp/typo.toml"
printf '[[class]\nname = "c"\n' >"$tmp/syntax.toml"
expect 2 "bad --class-config: $tmp/typo.toml:5:10: unknown key 'colour'" "$bin/hapsim-server" --listen 127.0.0.1:0 \
    --class-config "$tmp/typo.toml"
expect 2 "bad --class-config: $tmp/syntax.toml:1:" "$bin/hapsim-server" --listen 127.0.0.1:0 --class-config "$tmp/syntax.toml"
expect 2 "cannot read the class config" "$bin/hapsim-server" --listen 127.0.0.1:0 --class-config "$tmp/none.toml"
expect 1 "cannot read TLS key" "$bin/hapsim-server" --listen 127.0.0.1:0 --tls-cert "$tmp/none.pem" \
    --tls-key "$tmp/none.key"
expect 1 "TLS needs both a certificate and its key" "$bin/hapsim-server" --listen 127.0.0.1:0 --tls-cert "$tmp/x.pem"
expect 2 "cannot read token file" "$bin/hapsim-ctl" --server 127.0.0.1:9 --token-file "$tmp/none.token" list
expect 2 "cannot read TLS CA" "$bin/hapsim-ctl" --server 127.0.0.1:9 --tls-ca "$tmp/none.pem" list
expect 2 "needs TLS: give --tls-ca too" "$bin/hapsim-viewer" --session s --tls-cert "$tmp/c.pem" --tls-key "$tmp/c.key"
expect 2 "--count wants a whole number" "$bin/hapsim-ctl" --server 127.0.0.1:9 watch c --count 0
# The flag grammar every Flags executable shares (row 72), and --help: usage
# on stdout, exit 0, for all six executables (rows 72-79).
for prog in hapsim-server hapsim-bridge hapsim-load hapsim-viewer hapsim-ctl; do
  expect 2 "$prog: unknown flag --frobnicate (see --help)" "$bin/$prog" --frobnicate
  [ "$prog" = hapsim-ctl ] && continue  # its first argument that is not a flag is the command
  expect 2 "$prog: unexpected argument 'stray' (flags start with --; see --help)" "$bin/$prog" stray
done
expect 2 "bad value 'soon' for --timeout-s (see --help)" "$bin/hapsim-ctl" --timeout-s=soon list
for prog in hapsim-server hapsim-bridge hapsim-load hapsim-viewer hapsim-ctl hapsim-validate; do
  expect 0 "usage: $prog" bash -c '"$0" --help >&2' "$bin/$prog"
  expect 0 "^$prog [0-9]*\.[0-9]*\.[0-9]*$" bash -c '"$0" --version >&2' "$bin/$prog"
done
expect 2 "bad value 'abc' for --seconds (see --help)" "$bin/hapsim-bridge" --seconds abc
# The demo's DDS domain (DEMO_DDS_DOMAIN) is checked before anything is installed or built.
expect 2 "DEMO_DDS_DOMAIN must be a number in 0-232, not 'x'" env DEMO_DDS_DOMAIN=x "$here/../../deploy/demo.sh"
expect 2 "DEMO_DDS_DOMAIN must be in 0-232 (DDS's limit), not 300" env DEMO_DDS_DOMAIN=300 "$here/../../deploy/demo.sh"
expect 2 "bad value '5x' for --frame-rate-hz (see --help)" "$bin/hapsim-server" --frame-rate-hz 5x
expect 2 "bad value '99999999999' for --devices (see --help)" "$bin/hapsim-load" --devices 99999999999
expect 2 "flag --seconds needs a value (see --help)" "$bin/hapsim-bridge" --seconds
# hapsim-load's own plan flags (row 76).
expect 2 "--devices must be in \[1, 1024\]" "$bin/hapsim-load" --devices 0
expect 2 "--devices must be in \[1, 1024\]" "$bin/hapsim-load" --devices 2000
expect 2 "session 'a' is listed twice" "$bin/hapsim-load" --sessions a,a
expect 2 "--phase-spread-s must be >= 0" "$bin/hapsim-load" --phase-spread-s -1
expect 2 "--interval-s must be within 0 (off) or \[0.1, 1e7\]" "$bin/hapsim-load" --interval-s 0.05
expect 2 "--intervals-csv needs --interval-s" "$bin/hapsim-load" --intervals-csv "${TMPDIR:-/tmp}/x.csv"
# hapsim-ctl's own mistakes (row 78).
expect 2 "usage: hapsim-ctl" "$bin/hapsim-ctl"
expect 2 "unknown command 'frob' (see hapsim-ctl --help)" "$bin/hapsim-ctl" --server 127.0.0.1:9 frob
expect 2 "close needs a session id" "$bin/hapsim-ctl" --server 127.0.0.1:9 close
expect 2 "--timeout-s must be within (0, 3600\] (see --help)" "$bin/hapsim-ctl" --timeout-s 0 list
expect 2 "--param wants KEY=NUMBER, got 'k'" "$bin/hapsim-ctl" --server 127.0.0.1:9 create s --param k
# A file the process cannot use stops it with exit 1 naming the file
# (docs/reliability.md rows 66, 69, 70, 71, 79, 80).
printf 't_s,x\n0,abc\n' >"$tmp/bad-poses.csv"
expect 1 "cannot open pose log '$tmp/none.csv'" "$bin/hapsim-bridge" --backend replay --replay-file "$tmp/none.csv"
expect 1 "pose log line 2: field 2 is not a finite number" "$bin/hapsim-bridge" --backend replay \
    --replay-file "$tmp/bad-poses.csv"
expect 1 "cannot create DDS domain 0 from file $tmp/none.xml" "$bin/hapsim-server" --listen 127.0.0.1:0 \
    --dds-config "$tmp/none.xml"
expect 1 "cannot create DDS domain 0 from file $tmp/none.xml" "$bin/hapsim-bridge" --dds-config "$tmp/none.xml"
expect 1 "cannot create DDS participant (domain 0, config CYCLONEDDS_URI=file://$tmp/none.xml)" \
    env CYCLONEDDS_URI="file://$tmp/none.xml" "$bin/hapsim-bridge" --dds-config ""
expect 1 "cannot write --port-file $tmp/no-dir/port" "$bin/hapsim-server" --listen 127.0.0.1:0 \
    --port-file "$tmp/no-dir/port"
expect 1 "cannot connect to the server within 0.5" "$bin/hapsim-viewer" --session s --headless \
    --server 127.0.0.1:9 --connect-timeout-s 0.5
expect 2 "usage: hapsim-validate" bash -c '"$0" >&2' "$bin/hapsim-validate"  # usage on stdout
expect 2 "unknown command 'frobnicate'" "$bin/hapsim-validate" frobnicate --out "$tmp/v"
expect 2 "unknown argument '--bogus'" "$bin/hapsim-validate" puncture --out "$tmp/v" --bogus
expect 2 "--out DIR is required" "$bin/hapsim-validate" puncture
# Deadband coding's flags.
expect 2 "--model-deadband must be within \[0, 1\]" "$bin/hapsim-server" --listen 127.0.0.1:0 --model-deadband 2
expect 2 "--model-keepalive-ms must be within (0, --pose-timeout-ms\]" "$bin/hapsim-server" --listen 127.0.0.1:0 \
    --model-keepalive-ms 0
expect 2 "--pose-extrapolation-ms must be within \[0, --pose-timeout-ms\]" "$bin/hapsim-server" --listen 127.0.0.1:0 \
    --pose-extrapolation-ms 1000
expect 2 "--pose-deadband-mm must be within \[0, 10\]" "$bin/hapsim-bridge" --pose-deadband-mm 20
expect 2 "--pose-keepalive-ms must be within (0, 200\]" "$bin/hapsim-bridge" --pose-keepalive-ms 0
expect 2 "--pose-deadband-mm must be within \[0, 10\]" "$bin/hapsim-load" --pose-deadband-mm 20
# The network lab's link emulator and DDS config generator: named, before any device opens.
expect 2 "at least two --host are needed" "$bin/hapsim-linkem" --host a,10.77.0.1
expect 2 "--host b: unknown link key 'delay' (known: delay_ms," "$bin/hapsim-linkem" --host a,10.77.0.1 \
    --host b,10.77.0.2,delay=5
expect 2 "--host b: loss must be within \[0, 1\], got 2" "$bin/hapsim-linkem" --host a,10.77.0.1 --host b,10.77.0.2,loss=2
expect 2 "--host b: '10.77.0' is not an IPv4 address" "$bin/hapsim-linkem" --host a,10.77.0.1 --host b,10.77.0
expect 2 "hosts a and b share an address" "$bin/hapsim-linkem" --host a,10.77.0.1 --host b,10.77.0.1
expect 2 "--seconds must be within (0, 86400]" "$bin/hapsim-linkem" --host a,10.77.0.1 --host b,10.77.0.2 --seconds 0
expect 1 "cannot open network namespace hapsim-no-such-lab" "$bin/hapsim-linkem" --host hapsim-no-such-lab,10.77.0.1 \
    --host b,10.77.0.2 --seconds 1
expect 2 "--interface is required" bash "$here/../../deploy/make-dds-config.sh"
expect 2 "--discovery unicast needs --peer" bash "$here/../../deploy/make-dds-config.sh" --interface eth0 --discovery unicast
expect 2 "--max-participants must be within \[1, 120\]" bash "$here/../../deploy/make-dds-config.sh" --interface eth0 \
    --max-participants 500
echo "$failures failed"
[ "$failures" -eq 0 ]
