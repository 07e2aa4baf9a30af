"""Reads a capacity.sh result directory and prints the markdown table
(docs/performance.md, "Capacity"); writes every run's figures to
OUT_DIR/capacity.csv.

    python3 tests/bench/capacity_table.py OUT_DIR

Per run (runs/<mode>-<server>-<scene>-<N>/), over the window from just
before the clients start to just after they exit:
  late ticks %       sum of the N sessions' late_ticks deltas / sum of their
                     ticks deltas (hapsim-ctl list before and after)
  round trip         median over devices of each device's p50 / the worst
                     device's p99 / the largest max (ms)
  worst model age    largest model age of any device (ms)
  watchdog           warnings / fades / disarms summed over devices ("-" if
                     the client does not count them)
  CPU per tick       server utime+stime delta / session-ticks (µs); in
                     brackets, where the server has a metrics endpoint
                     (this build's, not a baseline's): the tick's own work,
                     the sessions' hapsim_session_tick_seconds_total delta /
                     their hapsim_session_ticks_total delta (wall time from
                     the tick's start to its scene stepped: the step, the
                     input and the listeners). The rest is the runtime's
                     cost per session-tick (CSV: tick_work_us_per_session_tick,
                     runtime_us_per_session_tick)
  (CSV only)         context_switches_per_session_tick: the server threads'
                     voluntary + involuntary switches delta / session-ticks
  UDP per tick       host Udp OutDatagrams delta / session-ticks
  RcvbufErrors       host Udp RcvbufErrors delta
A row marked † ran while something else used the network: the host sent more
than 1000 UDP datagrams/s in the 1 s sampled before or after it, with
nothing of the benchmark running.
The ddsperf row: medians of the per-second 50 % and 99 % figures, the
largest per-second max, doubled — ddsperf reports half the round trip (on a
lab link of 5 ms each way it says 5.06 ms) — so the column is a round trip
like the others; its UDP column is datagrams per round trip.
Runs with the deadband coding (capacity.sh's CODINGS) say so in the server
column ("current, deadband coding"); the others send every pose and model.
Runs across the network lab (capacity.sh's LINKS) name their link in the
server column ("current @ delay_ms=5"); their UDP figures are the server's and
the clients' namespaces together, and a line under the table gives each lab
run's emulator report (packets carried, drops, forwarding lateness).
"""
import csv
import glob
import json
import os
import re
import statistics
import sys

out = sys.argv[1]
BACKGROUND_LIMIT = 1000  # UDP datagrams/s from other programs before marking a row


def read_env(path):
    env = {}
    if os.path.exists(path):
        for line in open(path):
            if "=" in line:
                key, value = line.rstrip("\n").split("=", 1)
                env[key] = value
    return env


def read_snmp(path):
    """/proc/net/snmp Udp: header and value lines -> {field: int}"""
    lines = [line.split()[1:] for line in open(path)]
    return {k: int(v) for k, v in zip(lines[0], lines[1])}


def udp_delta(run_dir):
    try:
        before, after = read_snmp(f"{run_dir}/snmp_before.txt"), read_snmp(f"{run_dir}/snmp_after.txt")
    except (OSError, IndexError):
        return {}
    return {k: after[k] - before.get(k, 0) for k in after}


def cpu_seconds(path, clk_tck):
    """utime + stime of /proc/PID/stat (fields 14 and 15; the name may hold spaces)"""
    rest = open(path).read().rsplit(")", 1)[1].split()
    return (int(rest[11]) + int(rest[12])) / clk_tck


def thread_cpu_seconds(run_dir, clk_tck, names):
    """CPU seconds the server's threads named in `names` used during the run (threads_*.txt: comm|stat lines)"""
    def read(path):
        cpu = {}
        for line in open(path):
            comm, _, stat = line.rstrip("\n").partition("|")
            if comm in names and ")" in stat:
                rest = stat.rsplit(")", 1)[1].split()
                cpu[(comm, stat.split()[0])] = (int(rest[11]) + int(rest[12])) / clk_tck
        return cpu
    try:
        before, after = read(f"{run_dir}/threads_before.txt"), read(f"{run_dir}/threads_after.txt")
    except OSError:
        return None
    total = {}
    for key, seconds in after.items():
        total[key[0]] = total.get(key[0], 0.0) + seconds - before.get(key, 0.0)
    return total


def sessions(path):
    """hapsim-ctl list -> {session id: {field: value}} (the benchmark's cap-* sessions)"""
    table = {}
    if os.path.exists(path):
        for line in open(path):
            fields = line.split()
            if fields and fields[0].startswith("cap-"):
                table[fields[0]] = dict(f.split("=", 1) for f in fields[1:] if "=" in f)
    return table


def tick_deltas(run_dir):
    before, after = sessions(f"{run_dir}/list_before.txt"), sessions(f"{run_dir}/list_after.txt")
    ticks = late = 0
    for sid, a in after.items():
        b = before.get(sid, {})
        late_key = "late_ticks" if "late_ticks" in a else "deadline_misses"
        ticks += int(a.get("ticks", 0)) - int(b.get("ticks", 0))
        late += int(a.get(late_key, 0)) - int(b.get(late_key, 0))
    return ticks, late, len(after)


METRIC_SAMPLE = re.compile(r'^(hapsim_session_tick_seconds_total|hapsim_session_ticks_total)\{[^}]*session="(cap-[^"]*)"[^}]*\} (\S+)')


def session_metrics(path):
    """the server's /metrics text -> {(metric, session): value} for the benchmark's cap-* sessions"""
    values = {}
    for line in open(path):
        m = METRIC_SAMPLE.match(line)
        if m:
            values[(m.group(1), m.group(2))] = float(m.group(3))
    return values


def tick_work(run_dir):
    """(seconds of tick work, ticks) summed over the sessions between the two scrapes, or None"""
    try:
        before, after = session_metrics(f"{run_dir}/metrics_before.txt"), session_metrics(f"{run_dir}/metrics_after.txt")
    except OSError:
        return None
    work = sum(v - before.get(k, 0.0) for k, v in after.items() if k[0] == "hapsim_session_tick_seconds_total")
    ticks = sum(v - before.get(k, 0.0) for k, v in after.items() if k[0] == "hapsim_session_ticks_total")
    return (work, ticks) if ticks > 0 else None


PERCENTILES = re.compile(r"p50 ([\d.]+) / p99 ([\d.]+) / max ([\d.]+) ms \(n=(\d+)\)")


def bridge_device(path):
    """hapsim-bridge's summary (device-bridge/main.cpp PrintReport) -> device dict"""
    text = open(path).read()
    d = {"round_trip": None, "model_age": None, "warnings": None, "fades": None, "disarms": None,
         "models": 0, "poses": 0}
    for key, label in (("round_trip", "round trip"), ("model_age", "model age")):
        m = re.search(rf"^bridge: {label} " + PERCENTILES.pattern, text, re.M)
        if m and int(m.group(4)) > 0:
            d[key] = tuple(float(m.group(i)) for i in (1, 2, 3))
    m = re.search(r"poses sent (\d+)(?: \([^)]*\))?; force models received (\d+)", text)
    if m:
        d["poses"], d["models"] = int(m.group(1)), int(m.group(2))
    m = re.search(r"disarms (\d+), watchdog \w+(?: \(warnings (\d+), fades (\d+)\))?", text)
    if m:
        d["disarms"] = int(m.group(1))
        if m.group(2) is not None:
            d["warnings"], d["fades"] = int(m.group(2)), int(m.group(3))
    return d


def load_devices(path):
    """hapsim-load's JSON -> device dicts"""
    devices = []
    for dev in json.load(open(path))["per_device"]:
        def pct(key):
            p = dev[key]
            return (p["p50"], p["p99"], p["max"]) if p["count"] > 0 else None
        devices.append({"round_trip": pct("round_trip_ms"), "model_age": pct("model_age_ms"),
                        "warnings": dev["watchdog_warnings"], "fades": dev["watchdog_fades"],
                        "disarms": dev["watchdog_disarms"], "models": dev["models_received"],
                        "poses": dev["poses_sent"]})
    return devices


def event_sum(devices, key):
    values = [d[key] for d in devices]
    return None if not values or any(v is None for v in values) else sum(values)


def fmt(value, spec, missing="-"):
    return missing if value is None else format(value, spec)


def link_label(env):
    link = env.get("link", "loopback")
    return "" if link == "loopback" else f" @ {link}"


def core_busy(run_dir, core):
    """share of the drive window core `core` was busy (/proc/stat cpuN: all but idle and iowait), or None"""
    try:
        def read(suffix):
            for line in open(f"{run_dir}/cores_{suffix}.txt"):
                f = line.split()
                if f[0] == f"cpu{core}":
                    ticks = [int(x) for x in f[1:]]
                    return sum(ticks), ticks[3] + ticks[4]
        (total0, idle0), (total1, idle1) = read("before"), read("after")
        return 1.0 - (idle1 - idle0) / (total1 - total0)
    except (OSError, TypeError, ZeroDivisionError):
        return None


def emulator(run_dir):
    """the lab's emulator report (link.json) -> one line, or None on loopback"""
    try:
        report = json.load(open(f"{run_dir}/link.json"))
    except (OSError, ValueError):
        return None
    hosts = report["hosts"]
    carried = sum(h["sent_packets"] for h in hosts)
    dropped = sum(h[k] for h in hosts for k in h if k.startswith("dropped_"))
    late = report["lateness_us"]
    line = (f"{carried / report['elapsed_s']:.0f} packets/s carried, {dropped} dropped, forwarding lateness "
            f"p50 {late['p50']:.0f} / p99 {late['p99']:.0f} / max {late['max']:.0f} µs")
    try:  # the emulator's whole life (the lab's), against the report's elapsed time
        clk = int(read_env(f"{run_dir}/run.env").get("clk_tck", 100))
        line += f"; emulator {100 * cpu_seconds(f'{run_dir}/linkem_stat.txt', clk) / report['elapsed_s']:.0f} % of a core"
    except (OSError, IndexError, ValueError):
        pass
    busy = core_busy(run_dir, 1)
    if busy is not None:
        line += f", clients' core (with the emulator) busy {100 * busy:.0f} % while driving"
    return line


def run_row(run_dir):
    env = read_env(f"{run_dir}/run.env")
    row = {k: env.get(k, "") for k in ("mode", "server", "scene", "n")}
    if env.get("coding", "every") != "every":
        row["server"] += f", {env['coding']} coding"
    if env.get("recording", "off") == "on":
        row["server"] += ", recording"
    row["server"] += link_label(env)
    row["emulator"] = emulator(run_dir)
    row["recording_threads"] = None
    if env.get("recording", "off") == "on":
        row["recording_threads"] = thread_cpu_seconds(run_dir, int(env.get("clk_tck", 100)),
                                                      ("hapsim-record", "hapsim-database"))
    row["failure"] = env.get("failure", "")
    background = [int(env[k]) for k in ("background_udp_per_s_before", "background_udp_per_s_after") if k in env]
    row["background_udp_per_s"] = max(background) if background else None
    if row["failure"]:
        return row
    devices = []
    if env["mode"] == "load":
        if os.path.exists(f"{run_dir}/load.json"):
            devices = load_devices(f"{run_dir}/load.json")
    else:
        devices = [bridge_device(p) for p in sorted(glob.glob(f"{run_dir}/bridge-*.out"))]
    ticks, late, listed = tick_deltas(run_dir)
    udp = udp_delta(run_dir)
    clk = int(env.get("clk_tck", 100))
    cpu = None
    try:
        cpu = cpu_seconds(f"{run_dir}/stat_after.txt", clk) - cpu_seconds(f"{run_dir}/stat_before.txt", clk)
    except (OSError, IndexError, ValueError):
        pass
    switches = None
    try:
        switches = int(open(f"{run_dir}/ctxt_after.txt").read()) - int(open(f"{run_dir}/ctxt_before.txt").read())
    except (OSError, ValueError):
        pass
    wall = None
    try:
        wall = float(open(f"{run_dir}/wall_after.txt").read()) - float(open(f"{run_dir}/wall_before.txt").read())
    except (OSError, ValueError):
        pass
    work = tick_work(run_dir)
    work_us = work[0] * 1e6 / work[1] if work else None
    cpu_us = cpu * 1e6 / ticks if cpu is not None and ticks else None
    with_rt = [d["round_trip"] for d in devices if d["round_trip"]]
    ages = [d["model_age"][2] for d in devices if d["model_age"]]
    row.update({
        "devices": len(devices),
        "devices_without_models": sum(1 for d in devices if not d["round_trip"]),
        "sessions_listed": listed,
        "session_ticks": ticks,
        "late_ticks": late,
        "late_pct": 100.0 * late / ticks if ticks else None,
        "rt_p50_ms": statistics.median(r[0] for r in with_rt) if with_rt else None,
        "rt_p99_ms": max(r[1] for r in with_rt) if with_rt else None,
        "rt_max_ms": max(r[2] for r in with_rt) if with_rt else None,
        "model_age_max_ms": max(ages) if ages else None,
        "warnings": event_sum(devices, "warnings"),
        "fades": event_sum(devices, "fades"),
        "disarms": event_sum(devices, "disarms"),
        "poses_sent": sum(d["poses"] for d in devices),
        "models_received": sum(d["models"] for d in devices),
        "server_cpu_s": cpu,
        "cpu_us_per_session_tick": cpu_us,
        "tick_work_us_per_session_tick": work_us,
        "runtime_us_per_session_tick": cpu_us - work_us if cpu_us is not None and work_us is not None else None,
        "context_switches_per_session_tick": switches / ticks if switches is not None and ticks else None,
        "udp_out": udp.get("OutDatagrams"),
        "udp_in": udp.get("InDatagrams"),
        "udp_per_session_tick": udp["OutDatagrams"] / ticks if udp and ticks else None,
        "rcvbuf_errors": udp.get("RcvbufErrors"),
        "wall_s": wall,
        "client_rc": env.get("client_rc", ""),
        "server_rc": env.get("server_rc", ""),
    })
    return row


def ddsperf_row(run_dir):
    p50, p99, maxima, count = [], [], [], 0
    line = re.compile(r"size \d+ .*? 50% ([\d.]+)us .*? 99% ([\d.]+)us max ([\d.]+)us cnt (\d+)")
    for text in open(f"{run_dir}/ping.out"):
        m = line.search(text)
        if m and int(m.group(4)) > 0:
            p50.append(float(m.group(1)))
            p99.append(float(m.group(2)))
            maxima.append(float(m.group(3)))
            count += int(m.group(4))
    udp = udp_delta(run_dir)
    env = read_env(f"{run_dir}/run.env")
    background = [int(env[k]) for k in ("background_udp_per_s_before", "background_udp_per_s_after") if k in env]
    return {"background_udp_per_s": max(background) if background else None, "emulator": emulator(run_dir),
            "mode": "ddsperf ping/pong 1 kHz", "server": "-" + link_label(env), "scene": "-", "n": "1", "failure": "",
            "seconds": len(p50), "round_trips": count,
            # ddsperf's figures are half the round trip
            "rt_p50_ms": 2 * statistics.median(p50) / 1e3 if p50 else None,
            "rt_p99_ms": 2 * statistics.median(p99) / 1e3 if p99 else None,
            "rt_max_ms": 2 * max(maxima) / 1e3 if maxima else None,
            "udp_out": udp.get("OutDatagrams"),
            "udp_per_session_tick": udp["OutDatagrams"] / count if udp and count else None,
            "rcvbuf_errors": udp.get("RcvbufErrors")}


def table_line(r):
    if (r.get("background_udp_per_s") or 0) > BACKGROUND_LIMIT:
        r = dict(r, n=f"{r['n']} †")
    if r.get("failure"):
        return f"| {r['mode']} | {r['server']} | {r['scene']} | {r['n']} | failed: {r['failure']} |" + " |" * 6
    rt = " / ".join(fmt(r.get(k), ".3f") for k in ("rt_p50_ms", "rt_p99_ms", "rt_max_ms"))
    if r.get("devices_without_models"):
        rt += f" ({r['devices_without_models']} of {r['devices']} devices got no model)"
    events = " / ".join(fmt(r.get(k), "d") for k in ("warnings", "fades", "disarms"))
    if r["mode"].startswith("ddsperf"):
        late, age, events, cpu = "-", "-", "-", "-"
    else:
        late = fmt(r.get("late_pct"), ".2f")
        age = fmt(r.get("model_age_max_ms"), ".2f")
        cpu = fmt(r.get("cpu_us_per_session_tick"), ".1f")
        if r.get("tick_work_us_per_session_tick") is not None:
            cpu += f" ({fmt(r['tick_work_us_per_session_tick'], '.1f')})"
    return (f"| {r['mode']} | {r['server']} | {r['scene']} | {r['n']} | {late} | {rt} | {age} | {events} | {cpu} | "
            f"{fmt(r.get('udp_per_session_tick'), '.2f')} | {fmt(r.get('rcvbuf_errors'), 'd')} |")


rows = []
# loopback's first, then the lab's links
for ping in sorted(glob.glob(f"{out}/runs/ddsperf*/ping.out"), key=lambda p: ("ddsperf/" not in p, p)):
    rows.append(ddsperf_row(os.path.dirname(ping)))
for run_dir in open(f"{out}/runs.txt").read().split():
    rows.append(run_row(run_dir))

meta = read_env(f"{out}/meta.env")
print(f"capacity.sh {meta.get('date', '')}, commit {meta.get('commit', '?')}, {meta.get('cpus', '?')} CPUs "
      f"({meta.get('cpu', '?')}), {meta.get('run_s', '?')} s per run, script {meta.get('script', '?')}, "
      f"server on core 0, clients on core 1")
print()
print("| mode | server | scene | N | late ticks % | round trip p50 / p99 / max ms | worst model age ms | "
      "watchdog warnings / fades / disarms | server CPU µs per session-tick (the tick's own work) | UDP datagrams per session-tick | "
      "RcvbufErrors |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for r in rows:
    print(table_line(r))
lab_rows = [r for r in rows if r.get("emulator")]
if lab_rows:
    print()
    for r in lab_rows:
        print(f"- link emulator, {r['mode']} / {r['server']} / {r['scene']} / N={r['n']}: {r['emulator']}")
recorded = [r for r in rows if r.get("recording_threads") is not None and r.get("server_cpu_s")]
if recorded:
    print()
    for r in recorded:
        threads = r["recording_threads"]
        spent = sum(threads.values())
        per_tick = spent * 1e6 / r["session_ticks"] if r.get("session_ticks") else float("nan")
        print(f"- recording, {r['mode']} / {r['scene']} / N={r['n']}: its writer threads used "
              f"{100 * spent / r['server_cpu_s']:.2f} % of the server's CPU ({per_tick:.3f} µs per session-tick: "
              + ", ".join(f"{k} {v:.3f} s" for k, v in sorted(threads.items())) + ")")
marked = [r for r in rows if (r.get("background_udp_per_s") or 0) > BACKGROUND_LIMIT]
if marked:
    print()
    print(f"† another program sent UDP around this run (up to "
          f"{max(r['background_udp_per_s'] for r in marked)} datagrams/s with the benchmark idle): re-run it.")
if os.path.exists(f"{out}/notes.txt"):
    print()
    print(open(f"{out}/notes.txt").read().rstrip())

fields = ["mode", "server", "scene", "n", "failure", "devices", "devices_without_models", "sessions_listed",
          "session_ticks", "late_ticks", "late_pct", "rt_p50_ms", "rt_p99_ms", "rt_max_ms", "model_age_max_ms",
          "warnings", "fades", "disarms", "poses_sent", "models_received", "server_cpu_s",
          "cpu_us_per_session_tick", "context_switches_per_session_tick", "udp_out", "udp_in", "udp_per_session_tick", "rcvbuf_errors", "wall_s",
          "client_rc", "server_rc", "background_udp_per_s", "seconds", "round_trips",
          "tick_work_us_per_session_tick", "runtime_us_per_session_tick"]
with open(f"{out}/capacity.csv", "w", newline="") as f:
    writer = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
    writer.writeheader()
    for r in rows:
        writer.writerow({k: r.get(k) for k in fields})
