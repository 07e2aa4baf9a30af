"""Offline checks of deploy/k8s (no cluster here): every manifest parses;
the fields the deployment relies on hold together — the StatefulSet's
headless Service selects its pods, every mount has a volume, every
ConfigMap it names exists and holds a class config for each pod ordinal,
requests equal limits in whole CPUs (Guaranteed QoS for the static CPU
manager), the probes and ports are named consistently, and every server
flag in the args is one `hapsim-server --help` lists. yamllint and
`kubectl kustomize` run too where installed.
Usage: check_k8s.py K8S_DIR HAPSIM_SERVER"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import yaml

k8s_dir, server = sys.argv[1], sys.argv[2]
failures = 0


def check(ok, what):
    global failures
    print(("ok   " if ok else "FAIL ") + what)
    failures += 0 if ok else 1


kustomization = yaml.safe_load(open(os.path.join(k8s_dir, "kustomization.yaml")))
docs = []
for name in kustomization["resources"]:
    path = os.path.join(k8s_dir, name)
    check(os.path.exists(path), f"kustomization resource {name} exists")
    docs += [d for d in yaml.safe_load_all(open(path)) if d]
by_kind = {}
for d in docs:
    by_kind.setdefault(d["kind"], {})[d["metadata"]["name"]] = d
print(f"{len(docs)} objects: " + ", ".join(f"{k} {sorted(v)}" for k, v in sorted(by_kind.items())))

sts = by_kind["StatefulSet"]["hapsim"]
spec, pod = sts["spec"], sts["spec"]["template"]["spec"]
labels = sts["spec"]["template"]["metadata"]["labels"]
svc = by_kind["Service"].get(spec["serviceName"])
check(svc is not None and svc["spec"].get("clusterIP") == "None",
      f"serviceName {spec['serviceName']} is a headless Service")
check(all(labels.get(k) == v for k, v in svc["spec"]["selector"].items()), "the Service selects the pods")
check(spec["selector"]["matchLabels"].items() <= labels.items(), "the StatefulSet's selector matches its pods")
container = pod["containers"][0]
port_names = {p["name"] for p in container["ports"]}
check(all(p["targetPort"] in port_names for p in svc["spec"]["ports"]), "the Service's target ports are the pod's")
check(container["livenessProbe"]["tcpSocket"]["port"] in port_names, "the liveness probe names a pod port")
check("health" in container["readinessProbe"]["exec"]["command"], "readiness is the gRPC health check")

res = container["resources"]
check(res["requests"] == res["limits"], "requests equal limits (Guaranteed QoS)")
check(re.fullmatch(r"\d+", str(res["requests"]["cpu"])) is not None, "whole CPUs (the static CPU manager pins them)")

volumes = {v["name"]: v for v in pod["volumes"]}
claims = {c["metadata"]["name"] for c in spec.get("volumeClaimTemplates", [])}
for m in container["volumeMounts"]:
    check(m["name"] in volumes or m["name"] in claims, f"mount {m['mountPath']} has a volume")
check(any(m["mountPath"] == "/var/lib/hapsim" and m["name"] in claims for m in container["volumeMounts"]),
      "the data directory is the pod's own persistent volume")
for v in volumes.values():
    if "configMap" in v:
        check(v["configMap"]["name"] in by_kind.get("ConfigMap", {}), f"ConfigMap {v['configMap']['name']} is defined")

classes = by_kind["ConfigMap"]["hapsim-classes"]["data"]
for i in range(spec["replicas"]):
    check(f"class-hapsim-{i}.toml" in classes, f"pod hapsim-{i} has its class config")
# The directory names every pod by its stable name, at the Service's gRPC port.
directory = by_kind["ConfigMap"]["hapsim-directory"]["data"]["site.toml"]
grpc_port = next(p["port"] for p in by_kind["Service"]["hapsim"]["spec"]["ports"] if p["name"] == "grpc")
for i in range(spec["replicas"]):
    check(f'name = "hapsim-{i}"\naddress = "hapsim-{i}.hapsim:{grpc_port}"' in directory,
          f"the directory lists pod hapsim-{i} at hapsim-{i}.hapsim:{grpc_port}")
# Each pod's class config is one the server accepts, with the directory: it starts on them (and is stopped).
with tempfile.TemporaryDirectory() as tmp:
    directory_file = os.path.join(tmp, "site.toml")
    open(directory_file, "w").write(directory)
    for name, text in sorted(classes.items()):
        config, port_file = os.path.join(tmp, name), os.path.join(tmp, name + ".port")
        open(config, "w").write(text)
        pod = name[len("class-"):-len(".toml")]
        proc = subprocess.Popen([server, "--class-config", config, "--listen", "127.0.0.1:0", "--port-file", port_file,
                                 "--directory", directory_file, "--server-name", pod,
                                 "--dds-domain", str(200 + os.getpid() % 30), "--log-level", "error"],
                                stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        deadline = time.monotonic() + 10
        while not os.path.exists(port_file) and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        started = os.path.exists(port_file) and proc.poll() is None
        proc.terminate()
        _, err = proc.communicate(timeout=10)
        check(started, f"the server starts on {name}" + ("" if started else ": " + err.strip()[-300:]))
help_text = subprocess.run([server, "--help"], capture_output=True, text=True).stdout
mounts = [m["mountPath"] for m in container["volumeMounts"]]
for arg in container["args"]:
    flag, _, value = arg.partition("=")
    check(f"  {flag} " in help_text, f"{flag} is a hapsim-server flag")
    if value.startswith("/etc/") or value.startswith("/var/"):
        check(any(value.startswith(mp + "/") or value == mp for mp in mounts), f"{flag}'s {value} is mounted")

if shutil.which("yamllint"):
    r = subprocess.run(["yamllint", "-d", "{extends: default, rules: {line-length: {max: 120}, document-start: disable}}",
                        k8s_dir], capture_output=True, text=True)
    check(r.returncode == 0, "yamllint: clean" + ("" if r.returncode == 0 else "\n" + r.stdout))
else:
    print("skip yamllint is not installed")
if shutil.which("kubectl"):
    r = subprocess.run(["kubectl", "kustomize", k8s_dir], capture_output=True, text=True)
    check(r.returncode == 0, "kubectl kustomize renders the manifests offline")
else:
    print("skip kubectl is not installed (kubectl --dry-run needs a cluster's API for discovery anyway)")
sys.exit(1 if failures else 0)
