"""hapsim.MeshCache on hand-made frames: keyframes, deltas, topology edits, refusals.

The randomized round trip plays a server: a slot mesh edited and moved at
random, encoded the way docs/protocol.md describes, must come out of the
cache equal to the server's own compacted mesh after every frame.
"""
import random
import unittest
from typing import Dict, List, Optional, Tuple

import numpy as np

import hapsim
from hapsim._proto import viewer_pb2

QUANTUM = 1e-5  # [m]


def keyframe(seq: int = 0, version: int = 0, q: Optional[List[int]] = None, triangles: Optional[List[int]] = None,
             parts: Optional[List[int]] = None, free_vertices: Tuple[int, ...] = (),
             free_triangles: Tuple[int, ...] = (), vertex_capacity: int = 16, triangle_capacity: int = 16,
             quantum: float = QUANTUM) -> viewer_pb2.Frame:
    """Four vertices of a unit square (in quanta) and its two triangles, unless told otherwise."""
    q = q if q is not None else [0, 0, 0, 100, 0, 0, 100, 100, 0, 0, 100, 0]
    triangles = triangles if triangles is not None else [0, 1, 2, 0, 2, 3]
    parts = parts if parts is not None else [0] * (len(triangles) // 3)
    return viewer_pb2.Frame(seq=seq, topology_version=version, keyframe=viewer_pb2.Keyframe(
        quantum_m=quantum, positions_q=q, triangles=triangles, triangle_parts=parts, part_names=["skin", "wound"],
        layer_names=["skin"], free_vertices=free_vertices, free_triangles=free_triangles,
        vertex_capacity=vertex_capacity, triangle_capacity=triangle_capacity))


def delta(seq: int, version: int, moves: Dict[int, Tuple[int, int, int]], edits: Optional[List[int]] = None,
          from_version: Optional[int] = None) -> viewer_pb2.Frame:
    """A delta frame moving vertex slot -> (dqx, dqy, dqz), after ``edits`` if given."""
    slots = sorted(moves)
    gaps = [slots[0]] + [b - a for a, b in zip(slots, slots[1:])] if slots else []
    dq = [d for s in slots for d in moves[s]]
    frame = viewer_pb2.Frame(seq=seq, topology_version=version,
                             delta=viewer_pb2.MeshDelta(index_gaps=gaps, position_dq=dq))
    if edits is not None:
        frame.topology.from_version = from_version if from_version is not None else version - _edit_count(edits)
        frame.topology.edits.extend(edits)
    return frame


def _edit_count(edits: List[int]) -> int:
    i = n = 0
    while i < len(edits):
        i += 6 if edits[i] == 2 else 2
        n += 1
    return n


class KeyframeAndDeltas(unittest.TestCase):
    def test_keyframe_gives_positions_in_metres_and_triangles(self) -> None:
        cache = hapsim.MeshCache()
        cache.apply(keyframe())
        mesh = cache.mesh()
        self.assertEqual(mesh.positions_m.shape, (4, 3))
        np.testing.assert_allclose(mesh.positions_m[2], [1e-3, 1e-3, 0.0])
        np.testing.assert_array_equal(mesh.triangles, [[0, 1, 2], [0, 2, 3]])
        self.assertEqual(mesh.part_names, ("skin", "wound"))

    def test_delta_moves_listed_vertices_only(self) -> None:
        cache = hapsim.MeshCache()
        cache.apply(keyframe())
        cache.apply(delta(1, 0, {1: (5, 0, -7), 3: (0, 0, 12)}))
        p = cache.positions_m()
        np.testing.assert_allclose(p[1], [1.05e-3, 0.0, -0.07e-3])
        np.testing.assert_allclose(p[3], [0.0, 1e-3, 0.12e-3])
        np.testing.assert_allclose(p[0], [0.0, 0.0, 0.0])
        self.assertEqual(cache.last_seq, 1)

    def test_positions_add_modulo_2_to_the_32_like_the_encoder(self) -> None:
        cache = hapsim.MeshCache()
        cache.apply(keyframe(q=[2**31 - 1, 0, 0, 1, 0, 0, 2, 0, 0], triangles=[0, 1, 2]))
        cache.apply(delta(1, 0, {0: (1, 0, 0)}))
        self.assertAlmostEqual(cache.positions_m()[0, 0], -(2**31) * QUANTUM)

    def test_free_slots_of_a_keyframe_are_left_out(self) -> None:
        cache = hapsim.MeshCache()
        # Slot 1 free; triangle slot 0 free (zeros), triangle 1 uses 0, 2, 3.
        cache.apply(keyframe(q=[0, 0, 0, 0, 0, 0, 100, 0, 0, 0, 100, 0], triangles=[0, 0, 0, 0, 2, 3], parts=[0, 1],
                             free_vertices=(1,), free_triangles=(0,)))
        mesh = cache.mesh()
        self.assertEqual(mesh.positions_m.shape, (3, 3))
        np.testing.assert_array_equal(mesh.triangles, [[0, 1, 2]])  # slots 0, 2, 3 renumbered
        np.testing.assert_array_equal(mesh.triangle_parts, [1])


class Refusals(unittest.TestCase):
    def assert_refused(self, cache: hapsim.MeshCache, frame: viewer_pb2.Frame, reason: str) -> None:
        before = (cache.positions_m().copy(), cache.mesh().triangles.copy(), cache.topology_version, cache.last_seq)
        with self.assertRaises(hapsim.FrameRefused) as refused:
            cache.apply(frame)
        self.assertEqual(refused.exception.reason, reason, str(refused.exception))
        after = (cache.positions_m(), cache.mesh().triangles, cache.topology_version, cache.last_seq)
        np.testing.assert_array_equal(before[0], after[0])
        np.testing.assert_array_equal(before[1], after[1])
        self.assertEqual(before[2:], after[2:])

    def setUp(self) -> None:
        self.cache = hapsim.MeshCache()
        self.cache.apply(keyframe())

    def test_delta_before_keyframe(self) -> None:
        with self.assertRaises(hapsim.FrameRefused) as refused:
            hapsim.MeshCache().apply(delta(1, 0, {0: (1, 1, 1)}))
        self.assertEqual(refused.exception.reason, "need keyframe")

    def test_seq_gap(self) -> None:
        self.assert_refused(self.cache, delta(2, 0, {0: (1, 1, 1)}), "seq gap")

    def test_topology_mismatch(self) -> None:
        self.assert_refused(self.cache, delta(1, 3, {0: (1, 1, 1)}), "topology mismatch")

    def test_removing_a_vertex_a_triangle_uses(self) -> None:
        self.assert_refused(self.cache, delta(1, 1, {0: (9, 9, 9)}, edits=[1, 2]), "malformed frame")

    def test_edits_that_skip_a_version(self) -> None:
        self.assert_refused(self.cache, delta(1, 2, {}, edits=[0, 4], from_version=0), "malformed frame")

    def test_moving_a_free_or_unknown_vertex(self) -> None:
        self.assert_refused(self.cache, delta(1, 0, {7: (1, 0, 0)}), "malformed frame")

    def test_repeated_delta_index(self) -> None:
        frame = delta(1, 0, {1: (1, 0, 0)})
        frame.delta.index_gaps.append(0)
        frame.delta.position_dq.extend([1, 0, 0])
        self.assert_refused(self.cache, frame, "malformed frame")

    def test_triangle_on_a_free_vertex_and_unknown_edit(self) -> None:
        self.assert_refused(self.cache, delta(1, 1, {}, edits=[2, 2, 0, 0, 1, 9]), "malformed frame")
        self.assert_refused(self.cache, delta(1, 1, {}, edits=[7, 0]), "malformed frame")
        self.assert_refused(self.cache, delta(1, 1, {}, edits=[2, 2, 0, 0]), "malformed frame")  # truncated

    def test_bad_keyframes(self) -> None:
        self.assert_refused(self.cache, keyframe(quantum=0.0), "malformed frame")
        self.assert_refused(self.cache, keyframe(triangles=[0, 1, 9]), "malformed frame")
        self.assert_refused(self.cache, keyframe(triangles=[0, 1, 1]), "malformed frame")
        self.assert_refused(self.cache, keyframe(parts=[0, 5]), "malformed frame")
        self.assert_refused(self.cache, keyframe(free_vertices=(1,)), "malformed frame")  # used by a triangle
        self.assert_refused(self.cache, keyframe(vertex_capacity=2), "malformed frame")


class TopologyEdits(unittest.TestCase):
    def test_cut_adds_a_vertex_and_triangle_then_removes_the_old_ones(self) -> None:
        cache = hapsim.MeshCache()
        cache.apply(keyframe())
        # Add vertex slot 4 (beyond the keyframe's slots) and triangle slot 2 on it;
        # the delta carries the new vertex's absolute position.
        cache.apply(delta(1, 2, {4: (50, 50, -20)}, edits=[0, 4, 2, 2, 1, 1, 2, 4]))
        mesh = cache.mesh()
        self.assertEqual(mesh.positions_m.shape, (5, 3))
        np.testing.assert_allclose(mesh.positions_m[4], [0.5e-3, 0.5e-3, -0.2e-3])
        np.testing.assert_array_equal(mesh.triangles, [[0, 1, 2], [0, 2, 3], [1, 2, 4]])
        np.testing.assert_array_equal(mesh.triangle_parts, [0, 0, 1])
        # Remove triangles 0 and 1, then vertices 0 and 3 (no longer used).
        cache.apply(delta(2, 6, {}, edits=[3, 0, 3, 1, 1, 0, 1, 3]))
        mesh = cache.mesh()
        self.assertEqual(mesh.positions_m.shape, (3, 3))  # slots 1, 2, 4
        np.testing.assert_array_equal(mesh.triangles, [[0, 1, 2]])
        self.assertEqual(cache.topology_version, 6)


class RandomRoundTrip(unittest.TestCase):
    """A slot mesh edited at random; the cache must equal it after every frame."""

    def test_random_edits_and_moves(self) -> None:
        rng = random.Random(7)
        capacity = 40
        q: Dict[int, List[int]] = {v: [rng.randrange(-1000, 1000) for _ in range(3)] for v in range(12)}
        tris: Dict[int, Tuple[int, int, int, int]] = {}  # slot -> (part, a, b, c)
        for t in range(8):
            tris[t] = (t % 2, *rng.sample(sorted(q), 3))
        cache = hapsim.MeshCache()
        slots = max(q) + 1
        positions = [c for v in range(slots) for c in q.get(v, [0, 0, 0])]
        tri_words = [w for t in range(max(tris) + 1) for w in tris[t][1:]]
        cache.apply(keyframe(q=positions, triangles=tri_words, parts=[tris[t][0] for t in sorted(tris)],
                             vertex_capacity=capacity, triangle_capacity=capacity))
        version = 0
        for seq in range(1, 300):
            edits: List[int] = []
            moves: Dict[int, List[int]] = {}
            for _ in range(rng.randrange(0, 4)):
                used = {v for _, *abc in tris.values() for v in abc}
                choice = rng.random()
                free_v = [v for v in range(capacity) if v not in q]
                free_t = [t for t in range(capacity) if t not in tris]
                if choice < 0.3 and free_v:
                    v = rng.choice(free_v)
                    q[v] = [0, 0, 0]
                    edits += [0, v]
                    moves[v] = [rng.randrange(-1000, 1000) for _ in range(3)]  # its absolute position
                elif choice < 0.5:
                    removable = [v for v in q if v not in used and v not in moves]
                    if removable:
                        v = rng.choice(removable)
                        del q[v]
                        edits += [1, v]
                elif choice < 0.8 and free_t and len(q) >= 3:
                    t = rng.choice(free_t)
                    part, abc = rng.randrange(2), rng.sample(sorted(q), 3)
                    tris[t] = (part, *abc)
                    edits += [2, t, part, *abc]
                elif tris:
                    t = rng.choice(sorted(tris))
                    del tris[t]
                    edits += [3, t]
            for v in rng.sample(sorted(q), min(len(q), rng.randrange(0, 5))):
                dq = moves.get(v) or [0, 0, 0]
                moves[v] = [a + rng.randrange(-30, 31) for a in dq]
            for v, dq in moves.items():
                q[v] = [a + b for a, b in zip(q[v], dq)] if v in q else q[v]
            version += _edit_count(edits)
            frame = delta(seq, version, {v: tuple(d) for v, d in moves.items() if v in q},
                          edits=edits if edits else None, from_version=version - _edit_count(edits))
            cache.apply(frame)
            live_v = sorted(q)
            index_of = {v: i for i, v in enumerate(live_v)}
            mesh = cache.mesh()
            np.testing.assert_allclose(mesh.positions_m, np.array([q[v] for v in live_v]) * QUANTUM, rtol=0, atol=1e-12)
            expected = [[index_of[v] for v in tris[t][1:]] for t in sorted(tris)]
            np.testing.assert_array_equal(mesh.triangles, np.array(expected, dtype=np.uint32).reshape(-1, 3))
            np.testing.assert_array_equal(mesh.triangle_parts, [tris[t][0] for t in sorted(tris)])
        self.assertEqual(cache.topology_version, version)
        self.assertGreater(version, 100)


if __name__ == "__main__":
    unittest.main()
