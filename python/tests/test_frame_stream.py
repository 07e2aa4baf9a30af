"""hapsim.frames.subscribe against a scripted stub: acks, resubscribing, errors."""
import unittest
from typing import Iterator, List, Optional

import grpc

import hapsim
from hapsim._proto import viewer_pb2
from hapsim.frames import subscribe
from test_mesh_cache import delta, keyframe


class ScriptedCall:
    """One Subscribe stream: records the requests and plays the given frames."""

    def __init__(self, requests: Iterator[viewer_pb2.ViewerMessage], frames: List[viewer_pb2.Frame],
                 error: Optional[Exception] = None):
        self.requests = requests
        self.frames = frames
        self.error = error
        self.hello = next(requests)  # the SubscribeRequest comes first
        self.acks: List[int] = []
        self.cancelled = False

    def __iter__(self) -> Iterator[viewer_pb2.Frame]:
        for i, frame in enumerate(self.frames):
            if i > 0:  # the client acknowledges a frame before it takes the next
                self.acks.append(next(self.requests).ack.applied_seq)
            yield frame
        if self.error is not None:
            raise self.error

    def cancel(self) -> None:
        self.cancelled = True


class ScriptedStub:
    def __init__(self, *streams: List[viewer_pb2.Frame], error: Optional[Exception] = None):
        self.streams = list(streams)
        self.error = error
        self.calls: List[ScriptedCall] = []

    def Subscribe(self, requests, metadata=None, timeout=None) -> ScriptedCall:  # noqa: N802 (gRPC's name)
        frames = self.streams.pop(0) if self.streams else [delta(5, 0, {})]
        self.calls.append(ScriptedCall(requests, frames, self.error))
        return self.calls[-1]


class NotFoundError(grpc.RpcError):
    def code(self) -> grpc.StatusCode:
        return grpc.StatusCode.NOT_FOUND

    def details(self) -> str:
        return "no session 'x'"


class FrameStream(unittest.TestCase):
    def test_each_frame_is_acknowledged_before_the_next(self) -> None:
        stub = ScriptedStub([keyframe(), delta(1, 0, {0: (1, 0, 0)}), delta(2, 0, {0: (1, 0, 0)})])
        frames = list(subscribe(stub, "s1", [("authorization", "Bearer t")], max_frames=3))
        self.assertEqual([f.seq for f in frames], [0, 1, 2])
        self.assertAlmostEqual(frames[-1].positions_m[0, 0], 2e-5)
        call = stub.calls[0]
        self.assertEqual((call.hello.subscribe.session_id, call.hello.subscribe.ack_window), ("s1", 2))
        self.assertEqual(call.acks, [0, 1])
        self.assertTrue(call.cancelled)

    def test_a_refused_frame_resubscribes_for_a_keyframe(self) -> None:
        stub = ScriptedStub([keyframe(), delta(2, 0, {})],  # seq gap
                            [keyframe(), delta(1, 0, {3: (0, 0, 5)})])
        frames = list(subscribe(stub, "s1", [], max_frames=3))
        self.assertEqual([(f.seq, f.keyframe) for f in frames], [(0, True), (0, True), (1, False)])
        self.assertEqual(len(stub.calls), 2)
        self.assertTrue(stub.calls[0].cancelled)

    def test_refusals_in_a_row_raise(self) -> None:
        with self.assertRaises(hapsim.ProtocolError):
            list(subscribe(ScriptedStub(), "s1", []))  # every stream starts with a delta

    def test_grpc_errors_become_hapsim_errors(self) -> None:
        with self.assertRaises(hapsim.NotFound) as refused:
            list(subscribe(ScriptedStub([], error=NotFoundError()), "x", []))
        self.assertEqual(refused.exception.details, "no session 'x'")

    def test_the_stream_ending_ends_the_iteration(self) -> None:
        frames = list(subscribe(ScriptedStub([keyframe(), delta(1, 0, {})]), "s1", []))
        self.assertEqual(len(frames), 2)


if __name__ == "__main__":
    unittest.main()
