"""The channel to a server: plain TCP or TLS, and the bearer token of every call.

Mirrors the C++ clients (client-viewer/src/connection.cpp): TLS when a CA
is given, a client certificate for servers that require one, and the token
as ``authorization: Bearer TOKEN`` metadata on every call (on plain TCP
too, which development setups with a class config use).
"""
import os
from typing import List, Optional, Tuple

import grpc

# Keyframes of large meshes exceed gRPC's 4 MiB default (the viewer allows 64 MiB).
MAX_RECEIVE_BYTES = 64 << 20


def _read(path: str, what: str) -> bytes:
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError as error:
        raise ValueError(f"cannot read {what} {path}: {error.strerror}") from None


def resolve_token(token: Optional[str], token_file: Optional[str]) -> str:
    """The token: ``token_file``'s content, else ``token``, else $HAPSIM_TOKEN, else "" (none)."""
    if token_file:
        text = _read(token_file, "token file").decode().strip()
        if not text:
            raise ValueError(f"token file {token_file} is empty")
        return text
    if token:
        return token.strip()
    return os.environ.get("HAPSIM_TOKEN", "").strip()


def token_metadata(token: str) -> List[Tuple[str, str]]:
    return [("authorization", "Bearer " + token)] if token else []


def make_channel(target: str, tls_ca: Optional[str] = None, tls_cert: Optional[str] = None,
                 tls_key: Optional[str] = None, tls_server_name: Optional[str] = None) -> grpc.Channel:
    """A channel to ``target`` ("host:port"): TLS trusting ``tls_ca`` (PEM) if given, else plain TCP."""
    options = [("grpc.max_receive_message_length", MAX_RECEIVE_BYTES)]
    if not tls_ca:
        if tls_cert or tls_key or tls_server_name:
            raise ValueError("a client certificate or server name needs TLS: give tls_ca too")
        return grpc.insecure_channel(target, options=options)
    if bool(tls_cert) != bool(tls_key):
        raise ValueError("a client certificate needs both tls_cert and tls_key")
    credentials = grpc.ssl_channel_credentials(
        root_certificates=_read(tls_ca, "TLS CA"),
        private_key=_read(tls_key, "TLS client key") if tls_key else None,
        certificate_chain=_read(tls_cert, "TLS client certificate") if tls_cert else None)
    if tls_server_name:
        options.append(("grpc.ssl_target_name_override", tls_server_name))
    return grpc.secure_channel(target, credentials, options=options)
