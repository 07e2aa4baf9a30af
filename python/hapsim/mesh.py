"""A session's mesh rebuilt from its frame stream, in numpy.

The same rules as the viewer's MeshCache (client-viewer/src/mesh_cache.cpp,
docs/protocol.md): vertices and triangles live in stable slots; a keyframe
replaces the mesh; a delta frame first replays its topology edits (add or
remove a vertex or triangle, by slot), then moves the listed vertices by
q_new - q_old quanta. A delta is applied only if it is the stream's next
seq and starts from the topology version held; a malformed frame is
refused whole, before anything changes.
"""
import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from ._proto import viewer_pb2

# TopologyDelta.edits kinds.
ADD_VERTEX, REMOVE_VERTEX, ADD_TRIANGLE, REMOVE_TRIANGLE = 0, 1, 2, 3
# Refuse absurd capacities before allocating (as the C++ cache does).
MAX_SLOTS = 1 << 26


class FrameRefused(Exception):
    """A frame the cache cannot apply; the stream must start again from a keyframe.

    ``reason``: "need keyframe", "seq gap", "topology mismatch" or "malformed frame".
    """

    def __init__(self, reason: str, why: str):
        self.reason = reason
        self.why = why
        super().__init__(f"{reason}: {why}")


def _malformed(why: str) -> FrameRefused:
    return FrameRefused("malformed frame", why)


@dataclass(frozen=True)
class Mesh:
    """A mesh with only its live elements, vertices renumbered 0..N-1 in slot order."""

    positions_m: np.ndarray     # (N, 3) float64 vertex positions [m]
    triangles: np.ndarray       # (M, 3) uint32 rows of positions_m, counter-clockwise from outside
    triangle_parts: np.ndarray  # (M,) uint32 index into part_names
    part_names: Tuple[str, ...]  # "skin", "fat", "needle", ...


def _grown(array: np.ndarray, size: int) -> np.ndarray:
    """``array`` with at least ``size`` rows; new rows are zero (free slots)."""
    if size <= len(array):
        return array
    grown = np.zeros((max(size, 2 * len(array)),) + array.shape[1:], dtype=array.dtype)
    grown[:len(array)] = array
    return grown


class MeshCache:
    """The viewer-side copy of one session's mesh. Feed it every frame with ``apply``."""

    def __init__(self) -> None:
        self.has_mesh = False
        self.last_seq = 0
        self.topology_version = 0
        self.quantum_m = 0.0
        self.part_names: Tuple[str, ...] = ()
        self.layer_names: Tuple[str, ...] = ()
        self._vertex_capacity = 0
        self._triangle_capacity = 0
        # Per slot; arrays may be longer than the slots in use (free rows).
        self._q = np.zeros((0, 3), dtype=np.int32)
        self._vertex_live = np.zeros(0, dtype=bool)
        self._vertex_uses = np.zeros(0, dtype=np.int64)
        self._triangles = np.zeros((0, 3), dtype=np.int64)
        self._triangle_parts = np.zeros(0, dtype=np.int64)
        self._triangle_live = np.zeros(0, dtype=bool)
        self._topology_cache: Optional[Tuple[np.ndarray, np.ndarray]] = None

    def invalidate(self) -> None:
        """Forget the mesh (before resubscribing): the next frame must be a keyframe."""
        self.has_mesh = False

    def apply(self, frame: "viewer_pb2.Frame") -> None:
        """Apply one frame; raises FrameRefused (nothing changed) if it cannot."""
        kind = frame.WhichOneof("mesh")
        if kind == "keyframe":
            self._apply_keyframe(frame)
        elif kind == "delta":
            self._apply_delta(frame)
        else:
            raise _malformed("frame has neither keyframe nor delta")

    # -- the mesh as arrays --------------------------------------------------

    @property
    def live_vertex_count(self) -> int:
        return int(self._vertex_live.sum())

    @property
    def live_triangle_count(self) -> int:
        return int(self._triangle_live.sum())

    def positions_m(self) -> np.ndarray:
        """(N, 3) float64 positions of the live vertices in slot order [m] (a new array)."""
        return self._q[self._vertex_live].astype(np.float64) * self.quantum_m

    def mesh(self) -> Mesh:
        """The live mesh, compacted the way GetSnapshot compacts it."""
        triangles, parts = self.compact_topology()
        return Mesh(self.positions_m(), triangles, parts, self.part_names)

    def compact_topology(self) -> Tuple[np.ndarray, np.ndarray]:
        """(M, 3) uint32 live triangles indexing positions_m() rows, and their (M,) parts.

        Read-only arrays, kept until the topology changes (renumbering only
        changes with it).
        """
        if self._topology_cache is None:
            index_of = np.cumsum(self._vertex_live) - 1
            triangles = index_of[self._triangles[self._triangle_live]].astype(np.uint32).reshape(-1, 3)
            parts = self._triangle_parts[self._triangle_live].astype(np.uint32)
            for array in (triangles, parts):
                array.setflags(write=False)  # shared by every frame until the next edit
            self._topology_cache = (triangles, parts)
        return self._topology_cache

    # -- keyframes -------------------------------------------------------------

    def _apply_keyframe(self, frame: "viewer_pb2.Frame") -> None:
        key = frame.keyframe
        quantum = key.quantum_m
        if not (math.isfinite(quantum) and quantum > 0.0):
            raise _malformed("bad quantum")
        if len(key.positions_q) % 3 != 0:
            raise _malformed("positions not a multiple of 3")
        if len(key.triangles) != 3 * len(key.triangle_parts):
            raise _malformed("triangles and triangle parts do not match")
        n_vertices = len(key.positions_q) // 3
        n_triangles = len(key.triangle_parts)
        if not (n_vertices <= key.vertex_capacity <= MAX_SLOTS and n_triangles <= key.triangle_capacity <= MAX_SLOTS):
            raise _malformed("slot capacities smaller than the mesh or absurd")
        vertex_live = self._live_mask(n_vertices, key.free_vertices, "vertex")
        triangle_live = self._live_mask(n_triangles, key.free_triangles, "triangle")
        triangles = np.array(key.triangles, dtype=np.int64).reshape(-1, 3)
        parts = np.array(key.triangle_parts, dtype=np.int64)
        live = triangles[triangle_live]
        if live.size:
            in_range = bool((live < n_vertices).all())
            if (not in_range or not vertex_live[live].all() or (live[:, 0] == live[:, 1]).any()
                    or (live[:, 1] == live[:, 2]).any() or (live[:, 0] == live[:, 2]).any()):
                raise _malformed("a triangle names a free, repeated or unknown vertex")
            if (parts[triangle_live] >= len(key.part_names)).any():
                raise _malformed("a triangle has an unknown part")
        self.quantum_m = quantum
        self._vertex_capacity = key.vertex_capacity
        self._triangle_capacity = key.triangle_capacity
        self._q = np.array(key.positions_q, dtype=np.int32).reshape(-1, 3)
        self._vertex_live = vertex_live
        self._vertex_uses = np.bincount(live.ravel(), minlength=n_vertices).astype(np.int64)
        self._triangles = triangles
        self._triangle_parts = parts
        self._triangle_live = triangle_live
        self._topology_cache = None
        self.part_names = tuple(key.part_names)
        self.layer_names = tuple(key.layer_names)
        self.topology_version = frame.topology_version
        self.last_seq = frame.seq
        self.has_mesh = True

    @staticmethod
    def _live_mask(slots: int, free: Sequence[int], what: str) -> np.ndarray:
        live = np.ones(slots, dtype=bool)
        free_slots = np.array(free, dtype=np.int64)
        if free_slots.size and (free_slots.max() >= slots or len(np.unique(free_slots)) != free_slots.size):
            raise _malformed(f"bad free {what} slot")
        live[free_slots] = False
        return live

    # -- deltas ----------------------------------------------------------------

    def _apply_delta(self, frame: "viewer_pb2.Frame") -> None:
        if not self.has_mesh:
            raise FrameRefused("need keyframe", "delta before any keyframe")
        if frame.seq != self.last_seq + 1:
            raise FrameRefused("seq gap", f"expected seq {self.last_seq + 1}, got {frame.seq}")
        has_edits = frame.HasField("topology")
        from_version = frame.topology.from_version if has_edits else frame.topology_version
        if from_version != self.topology_version:
            raise FrameRefused("topology mismatch",
                               f"delta for topology {from_version}, cache holds {self.topology_version}")
        edits = list(frame.topology.edits) if has_edits else []
        added: Dict[int, bool] = {}  # vertex slots live (True) or free (False) once the edits are in
        if has_edits:
            count = self._check_topology(edits, added)
            # One edit per version: skipping or repeating versions would leave
            # the cache out of step with the server.
            if frame.topology_version != from_version + count:
                raise _malformed(f"{count} edits do not lead from topology {from_version} to {frame.topology_version}")
        delta = frame.delta
        if len(delta.position_dq) != 3 * len(delta.index_gaps):
            raise _malformed("delta needs 3 position values per index")
        gaps = np.array(delta.index_gaps, dtype=np.uint64)
        indices = np.cumsum(gaps, dtype=np.uint64)
        if gaps.size > 1 and (gaps[1:] == 0).any():
            raise _malformed("delta vertex indices not increasing")
        live_after = np.zeros(indices.size, dtype=bool)
        known = indices < len(self._vertex_live)
        live_after[known] = self._vertex_live[indices[known].astype(np.intp)]
        for slot, live in added.items():
            at = int(np.searchsorted(indices, slot))
            if at < indices.size and int(indices[at]) == slot:
                live_after[at] = live
        if not live_after.all():
            raise _malformed("delta vertex index not live")
        if has_edits:
            self._apply_topology(edits)
        if indices.size:
            dq = np.array(delta.position_dq, dtype=np.int32).reshape(-1, 3)
            # int32 arrays wrap on overflow: the modular add the encoder's
            # narrowed differences need, as in the C++ cache.
            self._q[indices.astype(np.intp)] += dq
        self.topology_version = frame.topology_version
        self.last_seq = frame.seq

    def _vertex_is_live(self, slot: int) -> bool:
        return slot < len(self._vertex_live) and bool(self._vertex_live[slot])

    def _triangle_is_live(self, slot: int) -> bool:
        return slot < len(self._triangle_live) and bool(self._triangle_live[slot])

    def _check_topology(self, edits: List[int], vertex_live: Dict[int, bool]) -> int:
        """Replays the edits on an overlay of the slots they touch; returns how many.

        Fills ``vertex_live`` with the vertex slots the edits leave live or free.
        """
        uses: Dict[int, int] = {}
        triangle_live: Dict[int, bool] = {}
        triangle_vertices: Dict[int, Tuple[int, int, int]] = {}

        def is_vertex_live(v: int) -> bool:
            return vertex_live[v] if v in vertex_live else self._vertex_is_live(v)

        def is_triangle_live(t: int) -> bool:
            return triangle_live[t] if t in triangle_live else self._triangle_is_live(t)

        def uses_of(v: int) -> int:
            if v not in uses:
                uses[v] = int(self._vertex_uses[v]) if v < len(self._vertex_uses) else 0
            return uses[v]

        i = count = 0
        while i < len(edits):
            if i + 2 > len(edits):
                raise _malformed("truncated edit")
            kind, slot = edits[i], edits[i + 1]
            if kind == ADD_VERTEX:
                if slot >= self._vertex_capacity or is_vertex_live(slot):
                    raise _malformed("add of a live or out-of-range vertex slot")
                vertex_live[slot] = True
                uses[slot] = 0
                i += 2
            elif kind == REMOVE_VERTEX:
                if not is_vertex_live(slot):
                    raise _malformed("removal of a free vertex slot")
                if uses_of(slot) != 0:
                    raise _malformed("removal of a vertex a live triangle still uses")
                vertex_live[slot] = False
                i += 2
            elif kind == ADD_TRIANGLE:
                if i + 6 > len(edits):
                    raise _malformed("truncated triangle edit")
                part, a, b, c = edits[i + 2:i + 6]
                if slot >= self._triangle_capacity or is_triangle_live(slot):
                    raise _malformed("add of a live or out-of-range triangle slot")
                if part >= len(self.part_names):
                    raise _malformed("triangle with an unknown part")
                if not (is_vertex_live(a) and is_vertex_live(b) and is_vertex_live(c)) or len({a, b, c}) != 3:
                    raise _malformed("triangle naming a free or repeated vertex")
                triangle_live[slot] = True
                triangle_vertices[slot] = (a, b, c)
                for v in (a, b, c):
                    uses[v] = uses_of(v) + 1
                i += 6
            elif kind == REMOVE_TRIANGLE:
                if not is_triangle_live(slot):
                    raise _malformed("removal of a free triangle slot")
                corners = triangle_vertices.get(slot) or tuple(int(v) for v in self._triangles[slot])
                for v in corners:
                    uses[v] = uses_of(v) - 1
                triangle_live[slot] = False
                i += 2
            else:
                raise _malformed(f"unknown edit kind {kind}")
            count += 1
        return count

    def _apply_topology(self, edits: List[int]) -> None:
        """Applies edits _check_topology accepted."""
        i = 0
        while i < len(edits):
            kind, slot = edits[i], edits[i + 1]
            if kind == ADD_VERTEX:
                if slot >= len(self._vertex_live):
                    self._q = _grown(self._q, slot + 1)
                    self._vertex_live = _grown(self._vertex_live, slot + 1)
                    self._vertex_uses = _grown(self._vertex_uses, slot + 1)
                self._vertex_live[slot] = True
                self._vertex_uses[slot] = 0
                self._q[slot] = 0  # the MeshDelta that follows carries its absolute position
                i += 2
            elif kind == REMOVE_VERTEX:
                self._vertex_live[slot] = False
                i += 2
            elif kind == ADD_TRIANGLE:
                if slot >= len(self._triangle_live):
                    self._triangles = _grown(self._triangles, slot + 1)
                    self._triangle_parts = _grown(self._triangle_parts, slot + 1)
                    self._triangle_live = _grown(self._triangle_live, slot + 1)
                self._triangle_live[slot] = True
                self._triangle_parts[slot] = edits[i + 2]
                self._triangles[slot] = edits[i + 3:i + 6]
                self._vertex_uses[edits[i + 3:i + 6]] += 1
                i += 6
            else:  # REMOVE_TRIANGLE
                self._triangle_live[slot] = False
                self._vertex_uses[self._triangles[slot]] -= 1
                i += 2
        self._topology_cache = None
