"""Checks of restart.sh: a server killed mid-class comes back with its
sessions, trials, scores and recordings; every recording replays exactly."""
import glob
import os
import re
import sys

from checks import check, exit_code, finish, read_text

work, server_rc = sys.argv[1], int(sys.argv[2])


def info_field(text, key):
    m = re.search(rf"{key}=([-0-9.]+)", text)
    return float(m.group(1)) if m else None


def replay_of(path):
    """(ticks, seconds of trial, checkpoints matched, recorded, resumes, speed x) of a hapsim-replay output."""
    text = read_text(work, path)
    m = re.search(r"replayed (\d+) ticks \(([0-9.]+) s of the trial\) in ([0-9.]+) s: ([0-9.]+)x", text)
    c = re.search(r"checkpoints: (\d+) of (\d+)", text)
    r = re.search(r"restarted (\d+) time", text)
    return (int(m.group(1)), float(m.group(2)), int(c.group(1)), int(c.group(2)), int(r.group(1)) if r else 0,
            float(m.group(4))) if m and c else None


log1 = read_text(work, "server1.log")
log2 = read_text(work, "server2.log")
check(exit_code(work, "reset_t1") == 0 and exit_code(work, "score1") == 0, "the instructor reset and scored t1")
check("brought back 3 of 3 sessions" in log2, "the second server says it brought back all 3 sessions")
for line in re.findall(r"session 't\d' brought back at tick .*", log2):
    print("  " + line)
listed = read_text(work, "list_after.out")
check(all(f"t{k} " in listed for k in (1, 2, 3)), "t1..t3 run again after the restart")

# State: the session went on from its recorded state.
info_before = read_text(work, "info_before.out")
sim_before = info_field(info_before, "sim_time_s")
t_info_end = float(read_text(work, "info_end_time"))
t_kill = float(read_text(work, "kill_time"))
replays_killed = {os.path.basename(f): f for f in glob.glob(f"{work}/replay_data_after_kill_*.out")}
t2_killed = [f for f in replays_killed if "_t2_" in f]
check(len(t2_killed) == 1, f"t2's recording as the kill left it ({t2_killed})")
if t2_killed:
    r = replay_of(t2_killed[0])
    check(r is not None and r[2] == r[3] and r[3] > 0, f"it replays to all its checkpoints ({r})")
    if r and sim_before is not None:
        recorded_s = r[1]
        # The session ticked at least until the info call returned, then on until the kill.
        lost_s = sim_before + (t_kill - t_info_end) - recorded_s
        print(f"t2: sim time at info {sim_before:.3f} s, recorded up to {recorded_s:.3f} s, "
              f"kill {1e3 * (t_kill - t_info_end):.0f} ms after the info call: lost <= {1e3 * lost_s:.0f} ms")
        check(lost_s <= 0.100, f"the kill lost <= 100 ms of t2's inputs ({1e3 * lost_s:.0f} ms)")
        early = info_field(read_text(work, "info_t2_early.out"), "sim_time_s")
        check(early is not None and early >= recorded_s,
              f"after the restart t2 went on from its recorded sim time ({early} >= {recorded_s:.3f} s)")
info_after = read_text(work, "info_after.out")
check(info_field(info_after, "device_streaming") == 1 and (info_field(info_after, "device_clocked_ticks") or 0) > 50,
      f"t2's device drove it again after the restart ({info_after.split()[6:12]})")

# Trials and scores from the database.
def trial_rows(name):
    rows = [line.split(",") for line in read_text(work, name).strip().splitlines()[1:]]
    return {(r[0], r[3]): r for r in rows}

before, after = trial_rows("trials_before.csv"), trial_rows("trials_after.csv")
t1_0_before, t1_0_after = before.get(("t1", "0")), after.get(("t1", "0"))
check(t1_0_before is not None and t1_0_before[4] == "reset", "before the kill: t1's trial 0 ended by the reset")
check(t1_0_after == t1_0_before, f"after the restart the same row comes back ({t1_0_after})")
check(("t1", "1") in after and ("t2", "0") in after, "t1's trial 1 and t2's trial 0 are listed after the restart")
scores_before = read_text(work, "scores_before.out")
scores_after = read_text(work, "scores_after.out")
check("t1" in scores_before and scores_before == scores_after, "the scores came back identical")

# Recordings: listed by role, fetched, replayed.
recordings = read_text(work, "recordings.out")
ids = [line.split()[0] for line in recordings.strip().splitlines()[1:]]
check(len(ids) == 4, f"4 recordings listed to the instructor (t1 trials 0 and 1, t2, t3): {ids}")
own = read_text(work, "recordings_trainee2.out").strip().splitlines()[1:]
check(len(own) == 1 and own[0].split()[1] == "t2", "trainee 2 sees only its own recording")
check(exit_code(work, "recordings_other") != 0, "trainee 2 may not list t1's recordings")
check(exit_code(work, "observer_delete") != 0, "an observer may not delete a recording")
check(exit_code(work, "delete_running") != 0 and "running trial" in read_text(work, "delete_running.err"),
      "a running trial's recording cannot be deleted")
check(exit_code(work, "delete_t1_0") == 0, "an ended trial's recording can be deleted")
check(len(read_text(work, "recordings_final.out").strip().splitlines()) == 4, "it is gone from the list")
check(all(exit_code(work, f"fetch_t{k}_0") == 0 for k in (1, 2, 3)), "every recording fetched over gRPC")
replays = sorted(glob.glob(f"{work}/replay_*.rc"))
check(len(replays) >= 9, f"{len(replays)} replays run (4 on disk, 4 fetched, 3+ as the kill left them)")
for rc in replays:
    name = os.path.basename(rc)[:-3]
    r = replay_of(f"{name}.out")
    check(exit_code(work, name) == 0 and r is not None and r[2] == r[3] and r[3] > 0,
          f"{name}: every checkpoint reached ({r})")
other = sorted(glob.glob(f"{work}/otherlibm_*.rc"))
check(len(other) == len(replays), f"{len(other)} recordings replayed again under GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA")
for rc in other:
    name = os.path.basename(rc)[:-3]
    r = replay_of(f"{name}.out")
    check(exit_code(work, name) == 0 and r is not None and r[2] == r[3] and r[3] > 0,
          f"{name}: every checkpoint reached on the other math paths ({r})")
resumed = [replay_of(f"{os.path.basename(rc)[:-3]}.out") for rc in replays if "data_recordings_t1" in rc]
check(any(r and r[4] >= 1 for r in resumed), "t1's running trial spans the kill: it holds a resume mark")
# Replays in the server.
def replay_fields(name):
    text = read_text(work, f"{name}.out")
    return {k: v for k, v in re.findall(r"(\w+)=([^ \n]+)", text)}

check(exit_code(work, "play_open") == 0, "trainee 1 opened a replay of its own trial 0")
done = replay_fields("play_done")
print(f"replay of t1's trial 0 at 4x after 1.5 s: {done}")
check(done.get("ended") == "1" and done.get("diverged") == "0" and done.get("matched") == done.get("checkpoints")
      and int(done.get("checkpoints", "0")) > 0, "it played to the end and reached every recorded hash")
viewer = read_text(work, "play_viewer.out")
m = re.search(r"frames (\d+) \(keyframes 1,", viewer)
check(exit_code(work, "play_viewer") == 0 and m is not None and int(m.group(1)) >= 30 and "gaps 0" in viewer,
      f"trainee 1 watched it: {m.group(1) if m else 0} frames in 1.5 s, no gap")
check(exit_code(work, "play_other") != 0, "trainee 2 may not see trainee 1's replay")
stepped, sought = replay_fields("play_stepped"), replay_fields("play_sought")
check(stepped.get("paused") == "1" and abs(float(stepped.get("trial_s", "-1")) - 0.5) < 1e-9,
      f"a paused replay stepped 500 ticks is 0.500 s into the trial ({stepped.get('trial_s')})")
check(sought.get("paused") == "1" and abs(float(sought.get("trial_s", "-1")) - 2.0) < 1e-9,
      f"sought to 2 s it is there, still paused ({sought.get('trial_s')})")
check(sought.get("rerun_ticks") == "2000", f"the first seek re-ran the trial's first 2 s ({sought.get('rerun_ticks')})")
back, back_stepped = replay_fields("play_back"), replay_fields("play_back_stepped")
check(exit_code(work, "play_back") == 0 and abs(float(back.get("trial_s", "-1")) - 1.2) < 1e-9
      and 0 < int(back.get("rerun_ticks", "-1")) < 500 and int(back.get("kept_states", "0")) >= 2,
      f"seeking back to 1.2 s re-ran only {back.get('rerun_ticks')} ticks, from one of the "
      f"{back.get('kept_states')} states kept at checkpoints (checkpoints every 500 ticks)")
check(back_stepped.get("diverged") == "0" and int(back_stepped.get("matched", "0")) >= 1,
      f"600 ticks on from there the replay reaches the recorded hashes ({back_stepped})")
check(exit_code(work, "play_close") == 0, "the instructor closed the replay")
if os.path.exists(f"{work}/console_past.rc"):  # built with the viewer GUI
    console = read_text(work, "console_past.out")
    print(console.strip())
    m = re.search(r"viewer: session (replay-\d+), frames (\d+)", console)
    check(exit_code(work, "console_past") == 0 and m is not None and int(m.group(2)) >= 30,
          f"the console opened t1's past trial as {m.group(1) if m else '?'} and watched "
          f"{m.group(2) if m else 0} frames")
    p = re.search(r"past trials (\d+) listed, replays opened 1, (replay-\d+) of (\S+) at [0-9.]+/[0-9.]+ s, "
                  r"checkpoints (\d+) matched 0 diverged", console)
    t1_0 = next((l.split()[0] for l in read_text(work, "recordings.out").splitlines()
                 if len(l.split()) > 2 and l.split()[1] == "t1" and l.split()[2] == "0"), None)
    check(p is not None and int(p.group(1)) >= 4 and p.group(3) == t1_0 and int(p.group(4)) >= 1,
          f"it listed the class's trials and its replay reached the recorded hashes ({p.group(0) if p else None})")
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from png_image import pixel, read_png
    image = read_png(f"{work}/past_trial.png")
    colours = {pixel(image, x, y) for x in range(0, 1280, 16) for y in range(0, 720, 16)}
    check(len(colours) > 50, f"the console's picture of the replay is not blank ({len(colours)} colours)")
    check(exit_code(work, "console_replay_closed") != 0, "closing the console closed its replay on the server")
check(server_rc == 0, f"the second server exited 0 ({server_rc})")
finish()
