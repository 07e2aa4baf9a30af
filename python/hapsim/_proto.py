"""The generated protobuf/gRPC modules, with a clear message when they are missing."""
try:
    from hapsim.v1 import session_pb2, session_pb2_grpc, viewer_pb2, viewer_pb2_grpc
except ImportError as error:  # pragma: no cover - depends on the environment
    raise ImportError(
        "hapsim: the generated modules hapsim.v1.*_pb2 are not on the path ({}). Build them "
        "(cmake --build build --target hapsim_python) and add the build tree's python folder, e.g. "
        "PYTHONPATH=python:build/python".format(error)) from error

__all__ = ["session_pb2", "session_pb2_grpc", "viewer_pb2", "viewer_pb2_grpc"]
