"""The instructor's class view (SessionService.WatchClass) as rows."""
import time
from dataclasses import dataclass
from typing import Iterator, List, Optional, Sequence, Tuple

import grpc

from ._proto import session_pb2, session_pb2_grpc
from .errors import ended_at_own_deadline, from_rpc_error
from .frames import Event


@dataclass(frozen=True)
class SessionStatus:
    """One session of the class at one update (SessionStatus in session.proto)."""

    session_id: str
    trainee: str                # the session's owner
    scene: str
    sim_time_s: float           # [s]
    tip_depth_m: float          # tool tip below the surface (0 outside) [m]
    current_layer: int          # -1: none
    layer_name: str
    force_n: float              # |force of the tissue on the tool| [N]
    contact_state: str          # free | contact | punctured | cutting
    events: List[Event]         # since this stream's previous update (its first: the newest 4)
    late_ticks: int
    max_tick_lateness_s: float  # [s]
    device_streaming: bool      # a pose arrived within the pose timeout
    paused: bool
    experts: int                # score sheets submitted
    score: Optional[float]      # comprehensive score so far, None while unscored
    ticks: int
    peak_tool_force_n: float    # [N]
    viewers: int
    events_total: int           # events the session has logged since it was created

    @staticmethod
    def from_proto(s: "session_pb2.SessionStatus") -> "SessionStatus":
        return SessionStatus(
            session_id=s.session_id, trainee=s.trainee, scene=s.scene, sim_time_s=s.sim_time_s,
            tip_depth_m=s.tip_depth_m, current_layer=s.current_layer, layer_name=s.layer_name, force_n=s.force_n,
            contact_state=s.contact_state, events=[Event.from_proto(e) for e in s.events], late_ticks=s.late_ticks,
            max_tick_lateness_s=s.max_tick_lateness_s, device_streaming=s.device_streaming, paused=s.paused,
            experts=s.experts, score=s.score if s.experts > 0 else None, ticks=s.ticks,
            peak_tool_force_n=s.peak_tool_force_n, viewers=s.viewers, events_total=s.events_total)


@dataclass(frozen=True)
class ClassUpdate:
    """One update of the class view: a row per running session, sorted by id."""

    class_name: str
    seq: int                        # 0, 1, 2, ... per stream
    sessions: List[SessionStatus]
    missing_sessions: Tuple[str, ...]  # sessions of the class not running now


def watch(stub: session_pb2_grpc.SessionServiceStub, class_name: str, metadata: Sequence[Tuple[str, str]],
          rate_hz: float = 10.0, max_updates: Optional[int] = None,
          seconds: Optional[float] = None) -> Iterator[ClassUpdate]:
    """Yields the class's updates at ``rate_hz`` [Hz] until ``max_updates`` or ``seconds`` [s]."""
    deadline = time.monotonic() + seconds if seconds is not None else None
    call = stub.WatchClass(session_pb2.WatchClassRequest(class_name=class_name, rate_hz=rate_hz),
                           metadata=metadata, timeout=seconds)
    updates = 0
    try:
        for status in call:
            yield ClassUpdate(status.class_name, status.seq,
                              [SessionStatus.from_proto(s) for s in status.sessions],
                              tuple(status.missing_sessions))
            updates += 1
            if max_updates is not None and updates >= max_updates:
                return
    except grpc.RpcError as error:
        if ended_at_own_deadline(error, deadline):
            return
        raise from_rpc_error(error) from None
    finally:
        call.cancel()
