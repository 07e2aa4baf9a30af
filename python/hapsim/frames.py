"""A session's frame stream (ViewerService.Subscribe) as numpy frames.

The stream acknowledges each frame once the caller has taken it, with a
small ack window (as hapsim-viewer does), so a slow consumer gets recent
frames instead of a growing backlog. A frame the mesh cache refuses (a gap
or a mismatch) ends the stream and starts a new one, which begins with a
keyframe.
"""
import queue
import time
from dataclasses import dataclass
from typing import Iterator, List, Optional, Sequence, Tuple

import grpc
import numpy as np

from ._proto import viewer_pb2, viewer_pb2_grpc
from .errors import ProtocolError, ended_at_own_deadline, from_rpc_error
from .mesh import FrameRefused, MeshCache

# Refusals in a row (no frame applied in between) before giving up.
_MAX_REFUSALS_IN_A_ROW = 5


@dataclass(frozen=True)
class Event:
    """A scene event: contact_begin, contact_end, puncture, cut_start, cut_end or reset."""

    t_s: float                 # sim time [s]
    kind: str
    layer: int                 # index into Frame.layer_names, -1 none
    where_m: Tuple[float, ...]  # (x, y, z) [m]
    value: float               # cut_end: the incision's length [m]

    @staticmethod
    def from_proto(e: "viewer_pb2.SceneEvent") -> "Event":
        return Event(e.t_s, e.kind, e.layer, tuple(e.where_m), e.value)


@dataclass(frozen=True)
class ToolState:
    """The tool as the frame's tick saw it."""

    tip_m: np.ndarray             # (3,) tip position [m]; (0,) while no device streams
    orientation_wxyz: np.ndarray  # (4,) unit quaternion
    force_n: np.ndarray           # (3,) force of the tissue on the tool [N]
    contact_state: str            # free | contact | punctured | cutting


@dataclass(frozen=True)
class Frame:
    """One applied frame: the whole live mesh at ``sim_time_s``.

    ``positions_m`` holds the live vertices in slot order (as GetSnapshot
    compacts them), ``triangles`` index its rows. Positions are the
    server's rounded to its quantum (10 um by default).
    """

    seq: int                    # 0, 1, ... per stream (0: the keyframe)
    sim_time_s: float           # [s]
    topology_version: int
    keyframe: bool              # this frame carried the whole mesh
    positions_m: np.ndarray     # (N, 3) float64 [m], a fresh array per frame
    triangles: np.ndarray       # (M, 3) uint32, read-only, shared until the topology changes
    triangle_parts: np.ndarray  # (M,) uint32 index into part_names, read-only
    part_names: Tuple[str, ...]
    layer_names: Tuple[str, ...]
    tool: ToolState
    current_layer: int          # index into layer_names, -1 none
    tip_depth_m: float          # tool tip below the surface (0 outside) [m]
    events: List[Event]         # since the previous frame of this stream
    paused: bool
    peak_force_n: float = 0.0   # peak |force on the tool| over the 1 kHz ticks since the previous frame [N]

    @property
    def vertex_count(self) -> int:
        return int(self.positions_m.shape[0])


def _to_frame(message: "viewer_pb2.Frame", cache: MeshCache) -> Frame:
    triangles, parts = cache.compact_topology()
    tool = message.tool
    return Frame(
        seq=message.seq,
        sim_time_s=message.sim_time_s,
        topology_version=message.topology_version,
        keyframe=message.WhichOneof("mesh") == "keyframe",
        positions_m=cache.positions_m(),
        triangles=triangles,
        triangle_parts=parts,
        part_names=cache.part_names,
        layer_names=cache.layer_names,
        tool=ToolState(np.array(tool.tip_m, dtype=np.float64), np.array(tool.orientation_wxyz, dtype=np.float64),
                       np.array(tool.force_n, dtype=np.float64), tool.contact_state),
        current_layer=message.current_layer,
        tip_depth_m=message.tip_depth_m,
        events=[Event.from_proto(e) for e in message.events],
        paused=message.paused,
        peak_force_n=message.peak_force_n,
    )


def _requests(outgoing: "queue.Queue[Optional[viewer_pb2.ViewerMessage]]") -> Iterator[viewer_pb2.ViewerMessage]:
    """The request side of one stream: gRPC reads it on its own thread; None ends it."""
    while True:
        message = outgoing.get()
        if message is None:
            return
        yield message


def subscribe(stub: viewer_pb2_grpc.ViewerServiceStub, session_id: str, metadata: Sequence[Tuple[str, str]],
              max_frames: Optional[int] = None, seconds: Optional[float] = None, max_rate_hz: float = 0.0,
              ack_window: int = 2, viewer_name: str = "hapsim-python") -> Iterator[Frame]:
    """Yields the session's frames until ``max_frames`` or ``seconds`` [s] (None: no limit).

    Ends quietly at either limit or when the server ends the stream; raises
    a hapsim.Error for a refused call (e.g. NotFound for an unknown session).
    """
    deadline = time.monotonic() + seconds if seconds is not None else None
    cache = MeshCache()
    delivered = 0
    refusals = 0
    while max_frames is None or delivered < max_frames:
        timeout = None
        if deadline is not None:
            timeout = deadline - time.monotonic()
            if timeout <= 0:
                return
        outgoing: "queue.Queue[Optional[viewer_pb2.ViewerMessage]]" = queue.Queue()
        outgoing.put(viewer_pb2.ViewerMessage(subscribe=viewer_pb2.SubscribeRequest(
            session_id=session_id, max_rate_hz=max_rate_hz, viewer_name=viewer_name, ack_window=ack_window)))

        call = stub.Subscribe(_requests(outgoing), metadata=metadata, timeout=timeout)
        cache.invalidate()
        refused: Optional[FrameRefused] = None
        try:
            for message in call:
                received_at = time.monotonic()
                try:
                    cache.apply(message)
                except FrameRefused as refusal:
                    refused = refusal
                    break
                refusals = 0
                yield _to_frame(message, cache)
                # Acknowledged once the caller is back for more, saying how
                # long that took: the server then sends at most ack_window
                # frames ahead of the caller beyond those still on the wire.
                held_us = int((time.monotonic() - received_at) * 1e6)
                outgoing.put(viewer_pb2.ViewerMessage(
                    ack=viewer_pb2.ViewerAck(applied_seq=message.seq, held_us=held_us)))
                delivered += 1
                if max_frames is not None and delivered >= max_frames:
                    return
        except grpc.RpcError as error:
            if ended_at_own_deadline(error, deadline):
                return
            raise from_rpc_error(error) from None
        finally:
            call.cancel()
            outgoing.put(None)
        if refused is None:
            return  # the server ended the stream (e.g. the session closed)
        refusals += 1
        if refusals >= _MAX_REFUSALS_IN_A_ROW:
            raise ProtocolError(None, f"{refusals} frames refused in a row, the last: {refused}")
