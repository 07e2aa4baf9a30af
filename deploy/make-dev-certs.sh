#!/usr/bin/env bash
# Makes a development CA and certificates for hapsim's gRPC TLS with openssl:
#   DIR/ca.pem, ca.key          the CA (trust it with --tls-ca / --tls-client-ca)
#   DIR/server.pem, server.key  the server's certificate (--tls-cert/--tls-key), valid for
#                               localhost, 127.0.0.1, ::1 and every extra NAME given
#   DIR/client.pem, client.key  a client certificate (for servers with --tls-client-ca)
# For development and tests only: keys are unencrypted EC P-256, valid 30 days.
# A real deployment gets its certificates from the site's CA.
#
# usage: deploy/make-dev-certs.sh DIR [NAME...]
set -euo pipefail
if [ $# -lt 1 ] || [ "$1" = "-h" ] || [ "$1" = "--help" ]; then
  sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'
  [ $# -ge 1 ] && exit 0 || exit 2
fi
command -v openssl >/dev/null || { echo "make-dev-certs: openssl not found (apt-get install openssl)" >&2; exit 1; }
dir=$1; shift
mkdir -p "$dir"
cd "$dir"
umask 077
san="DNS:localhost,IP:127.0.0.1,IP:0:0:0:0:0:0:0:1"
for name in "$@"; do
  if [[ $name =~ ^[0-9.]+$ ]]; then san+=",IP:$name"; else san+=",DNS:$name"; fi
done
key() { openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:P-256 -out "$1" 2>/dev/null; }

key ca.key
openssl req -x509 -new -key ca.key -sha256 -days 30 -subj "/CN=hapsim development CA" \
  -addext "basicConstraints=critical,CA:TRUE" -addext "keyUsage=critical,keyCertSign,cRLSign" -out ca.pem

sign() {  # name, subject, extensions
  key "$1.key"
  openssl req -new -key "$1.key" -subj "$2" -out "$1.csr"
  printf '%s\n' "$3" > "$1.ext"
  openssl x509 -req -in "$1.csr" -CA ca.pem -CAkey ca.key -CAcreateserial -sha256 -days 30 \
    -extfile "$1.ext" -out "$1.pem" 2>/dev/null
  rm -f "$1.csr" "$1.ext"
}
sign server "/CN=hapsim-server" "subjectAltName=$san
extendedKeyUsage=serverAuth"
sign client "/CN=hapsim-client" "extendedKeyUsage=clientAuth"
rm -f ca.srl
chmod 644 ca.pem server.pem client.pem
echo "make-dev-certs: wrote ca.pem server.pem server.key client.pem client.key to $(pwd) (server names: $san)"
