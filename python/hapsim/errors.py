"""Exceptions: one class per gRPC status the server documents (docs/protocol.md)."""
import time
from typing import Dict, Optional, Type

import grpc


class Error(Exception):
    """A call the server refused or that failed on the way.

    ``code`` is the gRPC status (``grpc.StatusCode``), ``details`` the
    server's message, e.g. "no session 'x'".
    """

    def __init__(self, code: Optional[grpc.StatusCode], details: str):
        self.code = code
        self.details = details
        name = code.name if code is not None else "ERROR"
        super().__init__(f"{name}: {details}")


class NotFound(Error):
    """Unknown session (NOT_FOUND)."""


class InvalidArgument(Error):
    """Bad id, unknown scene, bad parameter or scores (INVALID_ARGUMENT)."""


class AlreadyExists(Error):
    """A session with that id exists already (ALREADY_EXISTS)."""


class PermissionDenied(Error):
    """The token's role may not do this to this session or class (PERMISSION_DENIED)."""


class Unauthenticated(Error):
    """No token, or one the server does not know (UNAUTHENTICATED)."""


class Unavailable(Error):
    """No server there, or the TLS handshake failed (UNAVAILABLE)."""


class ResourceExhausted(Error):
    """Too many sessions or class watchers, or a request too large (RESOURCE_EXHAUSTED)."""


class ProtocolError(Error):
    """The server's frames could not be applied, even after resubscribing."""


_BY_CODE: Dict[grpc.StatusCode, Type[Error]] = {
    grpc.StatusCode.NOT_FOUND: NotFound,
    grpc.StatusCode.INVALID_ARGUMENT: InvalidArgument,
    grpc.StatusCode.ALREADY_EXISTS: AlreadyExists,
    grpc.StatusCode.PERMISSION_DENIED: PermissionDenied,
    grpc.StatusCode.UNAUTHENTICATED: Unauthenticated,
    grpc.StatusCode.UNAVAILABLE: Unavailable,
    grpc.StatusCode.RESOURCE_EXHAUSTED: ResourceExhausted,
}


def from_rpc_error(error: grpc.RpcError) -> Error:
    """The hapsim exception for a failed gRPC call (raise it ``from`` the original)."""
    code = error.code() if hasattr(error, "code") else None
    details = (error.details() if hasattr(error, "details") else None) or str(error)
    return _BY_CODE.get(code, Error)(code, details)


def ended_at_own_deadline(error: grpc.RpcError, deadline: Optional[float]) -> bool:
    """Whether a stream ended because the caller's own ``seconds`` ran out
    (``deadline`` on time.monotonic()), which is the normal end, not an error."""
    return (deadline is not None and error.code() == grpc.StatusCode.DEADLINE_EXCEEDED
            and time.monotonic() >= deadline - 0.05)
