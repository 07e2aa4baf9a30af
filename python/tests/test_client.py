#!/usr/bin/python3
"""hapsim.Client against real servers (ctest: python.client).

Starts build/bin/hapsim-server twice on 127.0.0.1 with a free port: in
development mode, and with a class config over TLS with tokens (the
certificates and class made by deploy/make-dev-certs.sh and make-class.sh).
Drives sessions with build/bin/hapsim-bridge. DDS stays on loopback (the
built-in config) on domains 10..38, which no other test uses. Every process
started here is stopped on exit, on SIGTERM (ctest's timeout) too.

usage: test_client.py --bin BUILD/bin --work DIR --deploy REPO/deploy [unittest args]
"""
import argparse
import atexit
import os
import shutil
import signal
import subprocess
import sys
import time
import unittest
from typing import Dict, List, Optional, Tuple

import numpy as np

import hapsim

ARGS = argparse.Namespace()
HALF_QUANTUM_M = 0.5e-5  # the server's default quantum is 10 um
_processes: List[subprocess.Popen] = []


def _stop(process: subprocess.Popen) -> Optional[int]:
    if process.poll() is None:
        process.terminate()
        try:
            process.wait(timeout=5)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
    return process.returncode


def _stop_all() -> None:
    for process in _processes:
        _stop(process)


atexit.register(_stop_all)


def _interrupted(*_: object) -> None:
    # unittest reports SystemExit as one test's error and goes on; an
    # interrupt ends the run, and atexit stops the servers.
    raise KeyboardInterrupt("SIGTERM")


signal.signal(signal.SIGTERM, _interrupted)  # ctest's timeout


def spawn(name: str, argv: List[str]) -> subprocess.Popen:
    """Starts ``argv`` with output to WORK/name.out/.err; retries while the binary is being rebuilt."""
    for attempt in range(5):
        try:
            with open(os.path.join(ARGS.work, name + ".out"), "w") as out, \
                    open(os.path.join(ARGS.work, name + ".err"), "w") as err:
                process = subprocess.Popen(argv, cwd=ARGS.work, stdin=subprocess.DEVNULL, stdout=out, stderr=err)
            _processes.append(process)
            return process
        except OSError:  # ENOENT / ETXTBSY while the linker replaces it
            if attempt == 4:
                raise
            time.sleep(2)
    raise AssertionError("unreachable")


def start_server(name: str, domain: int, *flags: str) -> Tuple[subprocess.Popen, str]:
    """hapsim-server on 127.0.0.1, port 0 (a free one); returns it and "127.0.0.1:PORT"."""
    port_file = os.path.join(ARGS.work, name + ".port")
    server = spawn(name, [os.path.join(ARGS.bin, "hapsim-server"), "--listen", "127.0.0.1:0", "--port-file", port_file,
                          "--dds-domain", str(domain), *flags])
    deadline = time.monotonic() + 15
    while time.monotonic() < deadline:
        port = read(port_file).strip() if os.path.exists(port_file) else ""
        if port:
            return server, "127.0.0.1:" + port
        if server.poll() is not None:
            break
        time.sleep(0.05)
    raise AssertionError(f"{name} did not start: {read(os.path.join(ARGS.work, name + '.err'))[-2000:]}")


def read(path: str) -> str:
    with open(path) as f:
        return f.read()


def bridge(name: str, session: str, domain: int, seconds: float, *flags: str) -> subprocess.Popen:
    return spawn(name, [os.path.join(ARGS.bin, "hapsim-bridge"), "--session", session, "--dds-domain", str(domain),
                        "--seconds", str(seconds), "--log-level", "warn", *flags])


def dds_domain() -> int:
    # 10..37 for the development server, +1 for the class server.
    return 10 + os.getpid() % 28


class DevelopmentServer(unittest.TestCase):
    """No class config: no tokens, plain TCP on loopback."""

    client: hapsim.Client
    domain: int

    @classmethod
    def setUpClass(cls) -> None:
        cls.domain = dds_domain()
        cls.server, cls.addr = start_server("dev-server", cls.domain,
                                            "--sessions", "py-static:tissue_block,py-drive:tissue_block")
        cls.client = hapsim.Client(cls.addr)

    @classmethod
    def tearDownClass(cls) -> None:
        cls.client.close()
        rc = _stop(cls.server)
        assert rc == 0, f"development server exited with {rc}"

    def test_scenes_are_listed_with_their_parameters(self) -> None:
        scenes = {s.name: s for s in self.client.scenes()}
        self.assertTrue({"tissue_block", "acupuncture", "cutting", "vessel"} <= set(scenes), sorted(scenes))
        acupuncture = {p.name: p for p in scenes["acupuncture"].parameters}
        self.assertEqual(acupuncture["skin_K_N_per_m"].unit, "N/m")
        self.assertEqual(acupuncture["skin_K_N_per_m"].default_value, 160.0)

    def test_create_list_close_round_trip(self) -> None:
        info = self.client.create_session("py-round-trip", "cutting", owner="alice")
        self.assertEqual((info.session_id, info.scene, info.owner), ("py-round-trip", "cutting", "alice"))
        listed = {s.session_id: s for s in self.client.list_sessions()}
        self.assertIn("py-round-trip", listed)
        self.assertEqual(listed["py-round-trip"].scene, "cutting")
        self.client.close_session("py-round-trip")
        self.assertNotIn("py-round-trip", {s.session_id for s in self.client.list_sessions()})
        generated = self.client.create_session(scene="tissue_block")  # the server picks the id
        self.assertTrue(generated.session_id)
        self.client.close_session(generated.session_id)

    def test_refusals_raise_their_exception_with_the_servers_message(self) -> None:
        with self.assertRaises(hapsim.NotFound) as not_found:
            self.client.close_session("py-nobody")
        self.assertIn("py-nobody", not_found.exception.details)
        self.assertEqual(not_found.exception.code.name, "NOT_FOUND")
        self.assertIsInstance(not_found.exception, hapsim.Error)
        with self.assertRaises(hapsim.NotFound):
            self.client.get_session("py-nobody")
        with self.assertRaises(hapsim.AlreadyExists):
            self.client.create_session("py-static", "tissue_block")
        with self.assertRaises(hapsim.InvalidArgument) as bad_scene:
            self.client.create_session("py-x", "no_such_scene")
        self.assertIn("no_such_scene", bad_scene.exception.details)
        with self.assertRaises(hapsim.InvalidArgument):
            self.client.create_session("py-x", "acupuncture", params={"patch_grid_nodes": 1000})
        with self.assertRaises(hapsim.InvalidArgument):
            self.client.create_session("bad id!", "tissue_block")

    def test_frames_are_arrays_equal_to_the_snapshot(self) -> None:
        # Paused, nothing moves: once a frame says so, the snapshot and every
        # later frame show the same mesh (frames rounded to the quantum).
        self.client.pause_session("py-static")
        snapshot: Optional[hapsim.Mesh] = None
        frames: List[hapsim.Frame] = []
        try:
            for frame in self.client.frames("py-static", max_frames=60):
                frames.append(frame)
                if frame.paused and snapshot is None:
                    snapshot = self.client.snapshot("py-static")
                    after = len(frames)
                if snapshot is not None and len(frames) >= after + 3:
                    break
        finally:
            self.client.resume_session("py-static")
        self.assertIsNotNone(snapshot, "a frame reported the pause")
        self.assertEqual([f.seq for f in frames], list(range(len(frames))))
        self.assertEqual([f.keyframe for f in frames], [True] + [False] * (len(frames) - 1))
        self.assertGreater(snapshot.positions_m.shape[0], 100)
        for f in frames:
            self.assertEqual(f.positions_m.shape, snapshot.positions_m.shape)
            self.assertEqual(f.positions_m.dtype, np.float64)
            self.assertTrue(np.isfinite(f.positions_m).all())
        last = frames[-1]
        self.assertTrue(last.paused)
        self.assertLessEqual(np.abs(last.positions_m - snapshot.positions_m).max(), HALF_QUANTUM_M + 1e-12)
        np.testing.assert_array_equal(last.triangles, snapshot.triangles)
        np.testing.assert_array_equal(last.triangle_parts, snapshot.triangle_parts)
        self.assertEqual(last.part_names, snapshot.part_names)

    def test_frames_of_an_unknown_session_raise_not_found(self) -> None:
        with self.assertRaises(hapsim.NotFound) as refused:
            next(iter(self.client.frames("py-nobody", max_frames=1)))
        self.assertIn("py-nobody", str(refused.exception))

    def test_a_driven_session_moves_its_vertices(self) -> None:
        # 10 mm above the surface, down to 5 mm deep at 20 mm/s, held, withdrawn.
        device = bridge("dev-bridge", "py-drive", self.domain, 3.0, "--script", "insertion", "--depth-mm", "5",
                        "--speed-mm-s", "20")
        start = time.monotonic()
        first: Optional[np.ndarray] = None
        moved_m, lowest_tip_m, frames, keyframes = 0.0, np.inf, 0, 0
        states: Dict[str, int] = {}
        times: List[float] = []
        for frame in self.client.frames("py-drive", seconds=8.0):
            frames += 1
            keyframes += frame.keyframe
            times.append(frame.sim_time_s)
            states[frame.tool.contact_state] = states.get(frame.tool.contact_state, 0) + 1
            if frame.tool.tip_m.size == 3:
                lowest_tip_m = min(lowest_tip_m, float(frame.tool.tip_m[2]))
            if first is None:
                first = frame.positions_m
            self.assertEqual(frame.positions_m.shape, first.shape)
            moved_m = max(moved_m, float(np.linalg.norm(frame.positions_m - first, axis=1).max()))
            if device.poll() is not None:
                break
        bridge_rc = device.wait(timeout=10)
        print(f"\n  driven session: {frames} frames in {time.monotonic() - start:.1f} s, {keyframes} keyframe, "
              f"vertices moved up to {moved_m * 1e3:.2f} mm, tip down to {lowest_tip_m * 1e3:.2f} mm, "
              f"states {states}", file=sys.stderr)
        self.assertEqual(bridge_rc, 0)
        self.assertEqual(keyframes, 1)  # one keyframe, then only deltas applied
        self.assertGreater(frames, 60)
        self.assertTrue(all(b > a for a, b in zip(times, times[1:])), "sim time increases frame to frame")
        self.assertGreater(moved_m, 1e-3, "the tissue was pressed in by more than 1 mm")
        self.assertLess(lowest_tip_m, -1e-3, "the tool tip went below the surface")
        self.assertIn("contact", states)

    def test_a_cut_arrives_as_topology_edits_and_ends_equal_to_the_server(self) -> None:
        # A 20 mm scalpel stroke, 1.5 mm deep: the cut reaches the client as
        # topology edits on delta frames (one keyframe in all); paused
        # afterwards, the client's mesh equals the server's snapshot.
        self.client.create_session("py-cut", "cutting")
        device = bridge("cut-bridge", "py-cut", self.domain, 4.0, "--script", "cut", "--start-height-mm", "5",
                        "--depth-mm", "1.5", "--speed-mm-s", "10", "--entry-x-mm", "-10", "--cut-length-mm", "20")
        frames: List[hapsim.Frame] = []
        snapshot: Optional[hapsim.Mesh] = None
        incisions_m: List[float] = []
        after = 0
        try:
            for frame in self.client.frames("py-cut", seconds=12.0):
                frames.append(frame)
                incisions_m += [e.value for e in frame.events if e.kind == "cut_end"]
                if snapshot is None and device.poll() is not None and not frame.paused:
                    self.client.pause_session("py-cut")
                if snapshot is None and frame.paused:
                    snapshot = self.client.snapshot("py-cut")
                    after = len(frames)
                if snapshot is not None and len(frames) >= after + 2:
                    break
            self.assertEqual(device.wait(timeout=10), 0)
        finally:
            self.client.close_session("py-cut")
        versions = [f.topology_version for f in frames]
        print(f"\n  cut: {len(frames)} frames, topology {versions[0]} -> {versions[-1]}, "
              f"incisions {[round(v * 1e3, 2) for v in incisions_m]} mm, "
              f"{frames[-1].vertex_count} vertices, {len(frames[-1].triangles)} triangles", file=sys.stderr)
        self.assertIsNotNone(snapshot, "a frame reported the pause")
        self.assertEqual(sum(f.keyframe for f in frames), 1, "edits applied, never a resubscribe")
        self.assertGreater(versions[-1], versions[0] + 10, "the cut changed the topology")
        self.assertTrue(incisions_m and incisions_m[0] > 10e-3, f"an incision longer than 10 mm: {incisions_m}")
        last = frames[-1]
        self.assertEqual(last.positions_m.shape, snapshot.positions_m.shape)
        self.assertLessEqual(np.abs(last.positions_m - snapshot.positions_m).max(), HALF_QUANTUM_M + 1e-12)
        np.testing.assert_array_equal(last.triangles, snapshot.triangles)
        np.testing.assert_array_equal(last.triangle_parts, snapshot.triangle_parts)

    def test_watch_class_without_a_class_lists_every_session(self) -> None:
        updates = list(self.client.watch_class("", rate_hz=20, max_updates=3))
        self.assertEqual([u.seq for u in updates], [0, 1, 2])
        ids = [s.session_id for s in updates[-1].sessions]
        self.assertEqual(ids, sorted(ids))
        self.assertIn("py-static", ids)
        row = next(s for s in updates[-1].sessions if s.session_id == "py-static")
        self.assertEqual(row.scene, "tissue_block")
        self.assertGreater(row.ticks, 0)
        self.assertIsNone(row.score)


class ClassroomOverTls(unittest.TestCase):
    """A class of two acupuncture trainees (target depth 10 mm) over TLS with tokens."""

    domain: int

    @classmethod
    def setUpClass(cls) -> None:
        cls.domain = dds_domain() + 1
        cls.dir = os.path.join(ARGS.work, "class")
        for script, args in (("make-dev-certs.sh", [os.path.join(cls.dir, "certs")]),
                             ("make-class.sh", [cls.dir, "acu-101", "2", "acupuncture", "10"])):
            subprocess.run(["bash", os.path.join(ARGS.deploy, script), *args], check=True, stdout=subprocess.DEVNULL)
        cls.ca = os.path.join(cls.dir, "certs", "ca.pem")
        cls.server, cls.addr = start_server(
            "class-server", cls.domain, "--class-config", os.path.join(cls.dir, "class.toml"),
            "--tls-cert", os.path.join(cls.dir, "certs", "server.pem"),
            "--tls-key", os.path.join(cls.dir, "certs", "server.key"))
        cls.instructor = cls.as_("instructor")

    @classmethod
    def tearDownClass(cls) -> None:
        cls.instructor.close()
        rc = _stop(cls.server)
        assert rc == 0, f"class server exited with {rc}"

    @classmethod
    def token_file(cls, who: str) -> str:
        return os.path.join(cls.dir, "tokens", who + ".token")

    @classmethod
    def as_(cls, who: str) -> hapsim.Client:
        return hapsim.Client(cls.addr, tls_ca=cls.ca, token=read(cls.token_file(who)).strip())

    def test_the_instructor_lists_the_class(self) -> None:
        sessions = {s.session_id: s.owner for s in self.instructor.list_sessions()}
        self.assertEqual(sessions, {"t1": "trainee1", "t2": "trainee2"})

    def test_a_wrong_or_missing_token_is_unauthenticated(self) -> None:
        os.environ.pop("HAPSIM_TOKEN", None)
        for token in ("0123456789abcdef" * 3, None):
            with hapsim.Client(self.addr, token=token, tls_ca=self.ca) as client:
                with self.assertRaises(hapsim.Unauthenticated):
                    client.list_sessions()
                with self.assertRaises(hapsim.Unauthenticated):
                    next(iter(client.frames("t1", max_frames=1)))

    def test_roles_are_enforced(self) -> None:
        with self.as_("observer") as observer:
            self.assertEqual(len(observer.list_sessions()), 2)
            with self.assertRaises(hapsim.PermissionDenied) as refused:
                observer.reset_session("t2")
            self.assertIn("observer", refused.exception.details)
        with self.as_("trainee1") as trainee:
            self.assertEqual(trainee.get_session("t1").session_id, "t1")
            with self.assertRaises(hapsim.PermissionDenied):
                trainee.get_session("t2")
            with self.assertRaises(hapsim.PermissionDenied):
                trainee.trials("acu-101")

    def test_plain_tcp_to_the_tls_port_is_unavailable(self) -> None:
        token = read(self.token_file("instructor")).strip()
        with hapsim.Client(self.addr, token=token, timeout_s=5) as client:
            with self.assertRaises(hapsim.Unavailable):
                client.list_sessions()

    def test_a_trainee_streams_its_session_with_a_token_file(self) -> None:
        with hapsim.Client(self.addr, token_file=self.token_file("trainee1"), tls_ca=self.ca) as trainee:
            frames = list(trainee.frames("t1", max_frames=3))
            snapshot = trainee.snapshot("t1")
        self.assertEqual([f.seq for f in frames], [0, 1, 2])
        self.assertEqual(frames[0].positions_m.shape, snapshot.positions_m.shape)
        self.assertEqual(frames[0].layer_names, ("skin", "fat", "muscle"))
        self.assertTrue(all(np.isfinite(f.positions_m).all() for f in frames))

    def test_a_driven_trial_comes_back_as_a_row(self) -> None:
        # A 12 mm insertion into t1 (2 mm past the class's 10 mm target), watched live.
        device = bridge("class-bridge", "t1", self.domain, 3.0, "--script", "insertion", "--depth-mm", "12",
                        "--speed-mm-s", "20", "--hold-s", "0.3")
        deepest_m, streaming, events, events_total = 0.0, False, [], 0
        quiet_since = None  # after the device's end: since when t1 logged nothing new
        for update in self.instructor.watch_class("acu-101", rate_hz=20, seconds=12.0):
            self.assertEqual(update.class_name, "acu-101")
            self.assertEqual([s.session_id for s in update.sessions], ["t1", "t2"])
            t1 = update.sessions[0]
            deepest_m = max(deepest_m, t1.tip_depth_m)
            streaming = streaming or t1.device_streaming
            if update.seq == 0:
                events_before = t1.events_total - len(t1.events)
            events += t1.events
            if device.poll() is not None and (quiet_since is None or t1.events_total != events_total):
                quiet_since = time.monotonic()
            events_total = t1.events_total
            if quiet_since is not None and time.monotonic() - quiet_since > 1.0:
                break
        self.assertEqual(device.wait(timeout=10), 0)
        self.assertTrue(streaming, "the class view saw t1's device streaming")
        self.assertGreater(deepest_m, 5e-3, "the class view saw the needle deeper than 5 mm")
        self.assertIn("puncture", [e.kind for e in events])
        # Every event logged while the stream watched came once, in order.
        self.assertEqual(events_before + len(events), events_total)
        self.assertEqual([e.t_s for e in events], sorted(e.t_s for e in events))
        # A stream opened now starts with t1's newest 4 events and its total.
        late = next(iter(self.instructor.watch_class("acu-101", rate_hz=20, max_updates=1))).sessions[0]
        self.assertEqual(late.events_total, events_total)
        self.assertEqual(late.events, events[-4:])

        self.instructor.reset_session("t1")  # ends t1's trial 0
        rows: List[hapsim.TrialRow] = []
        deadline = time.monotonic() + 3
        while time.monotonic() < deadline:
            rows = self.instructor.trials("acu-101")
            if any(r.session == "t1" and r.end == "reset" for r in rows):
                break
            time.sleep(0.1)
        ended = [r for r in rows if r.session == "t1" and r.end == "reset"]
        self.assertEqual(len(ended), 1, rows)
        trial = ended[0]
        print(f"\n  t1's trial: {trial}", file=sys.stderr)
        self.assertEqual((trial.trial, trial.trainee, trial.scene), (0, "trainee1", "acupuncture"))
        self.assertAlmostEqual(trial.max_depth_mm, 12.0, delta=0.5)
        self.assertEqual(trial.target_depth_mm, 10.0)
        self.assertAlmostEqual(trial.depth_error_mm, trial.max_depth_mm - 10.0, delta=0.002)
        self.assertIn("skin", trial.layers_pierced)
        self.assertGreaterEqual(trial.punctures, 1)
        self.assertGreater(trial.peak_force_N, 0.1)
        self.assertIn("skin", trial.peak_force_by_layer_N)
        self.assertIsNotNone(trial.time_to_contact_s)
        self.assertIsNone(trial.score)
        self.assertEqual(sorted(r.session for r in rows if r.end == "running"), ["t1", "t2"])

        # The same columns as hapsim-ctl trials --csv, and the same ended row.
        ctl = subprocess.run([os.path.join(ARGS.bin, "hapsim-ctl"), "--server", self.addr, "--tls-ca", self.ca,
                              "--token-file", self.token_file("instructor"), "trials", "acu-101"],
                             check=True, capture_output=True, text=True, timeout=20).stdout
        self.assertEqual(ctl.splitlines()[0].split(","), hapsim.TrialRow.columns())
        self.assertIn(trial, hapsim.parse_trials_csv(ctl))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bin", required=True, help="folder of hapsim-server, hapsim-bridge, hapsim-ctl")
    parser.add_argument("--work", required=True, help="scratch folder (emptied first): logs, certificates")
    parser.add_argument("--deploy", required=True, help="the repository's deploy/ folder")
    args, rest = parser.parse_known_args()
    vars(ARGS).update({k: os.path.abspath(v) for k, v in vars(args).items()})
    shutil.rmtree(ARGS.work, ignore_errors=True)
    os.makedirs(ARGS.work)
    start = time.monotonic()
    program = unittest.main(argv=[sys.argv[0], *rest], exit=False, verbosity=2)
    _stop_all()
    print(f"python.client: {time.monotonic() - start:.1f} s; logs in {ARGS.work}", file=sys.stderr)
    return 0 if program.result.wasSuccessful() else 1


if __name__ == "__main__":
    sys.exit(main())
