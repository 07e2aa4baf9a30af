"""hapsim: a Python client for the hapsim physics server.

A thin typed wrapper over the gRPC services of ``proto/hapsim/v1``:
connect (TLS, bearer token), list/create/close sessions, stream a session's
mesh as numpy arrays, watch a class, fetch the trials' metrics as rows.

The protobuf/gRPC modules are generated at build time into the build tree
(``build/python/hapsim/v1``), not kept in the sources: put both the source
folder and the build folder on the path, e.g.
``PYTHONPATH=python:build/python /usr/bin/python3 script.py``.

Units are SI and named in the fields (``positions_m``, ``force_n``).
"""
import os as _os
import pkgutil as _pkgutil

# The generated modules import themselves as ``hapsim.v1.*`` (the proto
# package), so this package spans two folders: these sources and the build
# tree's generated ``hapsim/v1``. extend_path finds every ``hapsim`` folder on
# sys.path; without one in a build tree, fall back to the checkout's build/.
__path__ = _pkgutil.extend_path(__path__, __name__)
_checkout_build = _os.path.join(_os.path.dirname(_os.path.dirname(_os.path.dirname(_os.path.abspath(__file__)))),
                                "build", "python", "hapsim")
if len(__path__) == 1 and _os.path.isdir(_checkout_build):
    __path__.append(_checkout_build)

from .errors import (AlreadyExists, Error, InvalidArgument, NotFound, PermissionDenied,  # noqa: E402
                     ProtocolError, ResourceExhausted, Unauthenticated, Unavailable)
from .mesh import FrameRefused, Mesh, MeshCache  # noqa: E402
from .frames import Event, Frame, ToolState  # noqa: E402
from .class_view import ClassUpdate, SessionStatus  # noqa: E402
from .trials import TrialRow, parse_trials_csv  # noqa: E402
from .client import Client  # noqa: E402

__all__ = [
    "Client",
    "Frame", "ToolState", "Event", "Mesh", "MeshCache", "FrameRefused",
    "ClassUpdate", "SessionStatus",
    "TrialRow", "parse_trials_csv",
    "Error", "NotFound", "InvalidArgument", "AlreadyExists", "PermissionDenied", "Unauthenticated",
    "Unavailable", "ResourceExhausted", "ProtocolError",
]
