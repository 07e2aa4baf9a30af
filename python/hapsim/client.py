"""hapsim.Client: the session service, frame streams, the class view and trials."""
from typing import Any, Callable, Iterator, List, Mapping, Optional

import grpc
import numpy as np

from . import class_view, frames as frame_stream
from ._proto import session_pb2, session_pb2_grpc, viewer_pb2_grpc
from .class_view import ClassUpdate
from .connection import make_channel, resolve_token, token_metadata
from .errors import from_rpc_error
from .frames import Frame
from .mesh import Mesh
from .trials import TrialRow, parse_trials_csv


class Client:
    """A connection to one hapsim-server.

    ``token`` (or ``token_file``, else $HAPSIM_TOKEN) goes with every call as
    ``authorization: Bearer TOKEN``; a server without a class config needs
    none. ``tls_ca`` (PEM file) connects over TLS trusting that CA;
    ``tls_cert``/``tls_key`` add a client certificate, ``tls_server_name``
    checks that name in the server's certificate. ``timeout_s`` [s] bounds
    each unary call.

    Refusals raise hapsim.Error subclasses: NotFound, InvalidArgument,
    AlreadyExists, PermissionDenied, Unauthenticated, Unavailable, ...

        with hapsim.Client("127.0.0.1:50051") as client:
            client.create_session("s1", "tissue_block")
            for frame in client.frames("s1", max_frames=10):
                print(frame.sim_time_s, frame.positions_m.shape)
    """

    def __init__(self, target: str = "127.0.0.1:50051", token: Optional[str] = None, tls_ca: Optional[str] = None,
                 *, token_file: Optional[str] = None, tls_cert: Optional[str] = None, tls_key: Optional[str] = None,
                 tls_server_name: Optional[str] = None, timeout_s: float = 10.0):
        self.target = target
        self.timeout_s = timeout_s
        self._metadata = token_metadata(resolve_token(token, token_file))
        self._channel = make_channel(target, tls_ca, tls_cert, tls_key, tls_server_name)
        self._sessions = session_pb2_grpc.SessionServiceStub(self._channel)
        self._viewer = viewer_pb2_grpc.ViewerServiceStub(self._channel)

    def close(self) -> None:
        """Closes the channel (streams still open end)."""
        self._channel.close()

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, *_: Any) -> None:
        self.close()

    def _call(self, method: Callable[..., Any], request: Any) -> Any:
        try:
            return method(request, metadata=self._metadata, timeout=self.timeout_s)
        except grpc.RpcError as error:
            raise from_rpc_error(error) from None

    # -- scenes and sessions ---------------------------------------------------

    def scenes(self) -> List["session_pb2.SceneInfo"]:
        """Every scene with its parameters (name, unit, default, bounds, description)."""
        return list(self._call(self._sessions.ListScenes, session_pb2.ListScenesRequest()).scenes)

    def list_sessions(self) -> List["session_pb2.SessionInfo"]:
        """The sessions the token may see, with their counters (SessionInfo in session.proto)."""
        return list(self._call(self._sessions.ListSessions, session_pb2.ListSessionsRequest()).sessions)

    def get_session(self, session_id: str) -> "session_pb2.SessionInfo":
        return self._call(self._sessions.GetSession, session_pb2.SessionRef(session_id=session_id))

    def create_session(self, session_id: str = "", scene: str = "tissue_block",
                       params: Optional[Mapping[str, float]] = None, owner: str = "") -> "session_pb2.SessionInfo":
        """Creates a session of ``scene``; an empty ``session_id`` lets the server pick one.

        ``params``: scene parameters by name, SI units as the names say
        (``scenes()`` lists them), e.g. ``{"needle_radius_m": 0.0004}``.
        """
        request = session_pb2.CreateSessionRequest(scene=scene, session_id=session_id, owner=owner,
                                                   params=dict(params or {}))
        return self._call(self._sessions.CreateSession, request)

    def close_session(self, session_id: str) -> None:
        self._call(self._sessions.CloseSession, session_pb2.SessionRef(session_id=session_id))

    def pause_session(self, session_id: str) -> "session_pb2.SessionInfo":
        return self._call(self._sessions.PauseSession, session_pb2.SessionRef(session_id=session_id))

    def resume_session(self, session_id: str) -> "session_pb2.SessionInfo":
        return self._call(self._sessions.ResumeSession, session_pb2.SessionRef(session_id=session_id))

    def reset_session(self, session_id: str) -> "session_pb2.SessionInfo":
        """Restarts the scene; ends the session's current trial (``trials()``)."""
        return self._call(self._sessions.ResetSession, session_pb2.SessionRef(session_id=session_id))

    def snapshot(self, session_id: str) -> Mesh:
        """The session's current mesh at full precision (live vertices in slot order)."""
        s = self._call(self._sessions.GetSnapshot, session_pb2.SessionRef(session_id=session_id))
        return Mesh(positions_m=np.array(s.positions_m, dtype=np.float64).reshape(-1, 3),
                    triangles=np.array(s.triangles, dtype=np.uint32).reshape(-1, 3),
                    triangle_parts=np.array(s.triangle_parts, dtype=np.uint32),
                    part_names=tuple(s.part_names))

    # -- streams ---------------------------------------------------------------

    def frames(self, session_id: str, max_frames: Optional[int] = None, seconds: Optional[float] = None,
               max_rate_hz: float = 0.0) -> Iterator[Frame]:
        """Yields the session's mesh frames: (N, 3) vertex positions [m], triangles, tool, events.

        Stops after ``max_frames`` frames or ``seconds`` [s] (None: until the
        server ends the stream); ``max_rate_hz`` [Hz] lowers the server's
        frame rate (0: its own). Iterating raises NotFound for an unknown session.
        """
        return frame_stream.subscribe(self._viewer, session_id, self._metadata, max_frames=max_frames,
                                      seconds=seconds, max_rate_hz=max_rate_hz)

    def watch_class(self, class_name: str = "", rate_hz: float = 10.0, max_updates: Optional[int] = None,
                    seconds: Optional[float] = None) -> Iterator[ClassUpdate]:
        """Yields the class view at ``rate_hz`` [Hz]: a SessionStatus row per running session.

        Without a class config on the server, ``class_name`` "" watches every session.
        """
        return class_view.watch(self._sessions, class_name, self._metadata, rate_hz=rate_hz,
                                max_updates=max_updates, seconds=seconds)

    # -- assessment ------------------------------------------------------------

    def trials(self, class_name: str = "") -> List[TrialRow]:
        """Every trial of the class with its automatic metrics: ended trials, then running ones."""
        report = self._call(self._sessions.GetTrials, session_pb2.TrialQuery(class_name=class_name))
        return parse_trials_csv(report.csv)
