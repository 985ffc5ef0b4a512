#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Create-and-delete cycles, each run on a fresh server: the shape that
caught a rare descriptor leak (docs/reliability.md, "Found and stopped")
where one long-lived server did not.

    tools/fresh_server_cycles.py --causticd build/bin/causticd --runs 150

Each run starts `causticd serve` on a loopback port with the campaign's
sessions settings, takes the server's descriptors one second after its
first session as the baseline, makes CYCLES sessions (POST then DELETE at
once, from 127.0.0.30-39 as the campaign does), and waits up to 10 s for
the descriptors to come back within 4 of the baseline. A run that ends
over it is waited on 20 s more, and its descriptors, sockets and threads
are kept in its folder. Runs `stress-ng` beside it yourself; bounded by
--runs, every request by a 30 s timeout. Exits 1 when a run kept
descriptors.
"""
import argparse, http.client, json, os, re, shutil, subprocess, sys, tempfile, threading, time

SPARE_FDS = 4
CONFIG = {"ice_addresses": "127.0.0.1", "width": "256", "height": "256", "framerate": "15",
          "max_sessions": "4", "max_sessions_per_address": "2", "idle_timeout_s": "3",
          "viewer_timeout_s": "3", "rate_limit_per_s": "20", "rate_limit_burst": "40"}


def descriptor_kinds(pid):
    kinds = {}
    for fd in os.listdir(f"/proc/{pid}/fd"):
        try:
            target = re.sub(r"\[\d+\]", "", os.readlink(f"/proc/{pid}/fd/{fd}"))
        except OSError:
            continue
        kinds[target] = kinds.get(target, 0) + 1
    return kinds


def one_run(binary, folder, cycles, log_level):
    os.makedirs(folder + "/state", exist_ok=True)
    config = dict(CONFIG, log_level=log_level, state_dir=folder + "/state")
    with open(folder + "/causticd.conf", "w") as f:
        f.write("".join(f"{k} = {v}\n" for k, v in config.items()))
    with open(folder + "/stderr.log", "w") as err, open(folder + "/stdout.log", "w") as out:
        server = subprocess.Popen([binary, "serve", "--port", "0", "--bind", "127.0.0.1", "--config",
                                   folder + "/causticd.conf"], stdout=subprocess.PIPE, stderr=err, text=True)
        try:
            port = None
            for line in server.stdout:
                out.write(line)
                if m := re.search(r"listening on http://[^:]+:(\d+)", line):
                    port = int(m.group(1))
                    break
            if port is None:
                return f"the server did not start (see {folder}/stderr.log)"
            threading.Thread(target=shutil.copyfileobj, args=(server.stdout, out), daemon=True).start()

            def request(method, path, body=None, token=None, source="127.0.0.1"):
                c = http.client.HTTPConnection("127.0.0.1", port, timeout=30, source_address=(source, 0))
                headers = {"Content-Type": "application/json"}
                if token:
                    headers["Authorization"] = "Bearer " + token
                c.request(method, path, body=body, headers=headers)
                r = c.getresponse()
                data = r.read()
                c.close()
                return r.status, data

            def cycle(scene, source):
                status, body = request("POST", "/api/v1/sessions", json.dumps({"scene": scene}), source=source)
                if status != 201:
                    return f"POST answered {status}"
                s = json.loads(body)
                request("DELETE", "/api/v1/sessions/" + s["id"], token=s["token"])
                request("GET", "/api/v1/sessions/" + s["id"] + "/params", token=s["token"])
                return None

            scenes = [s["id"] for s in json.loads(request("GET", "/api/v1/scenes")[1])["scenes"]]
            cycle(scenes[0], "127.0.0.1")  # loads the plugins and starts the pools meant to stay
            time.sleep(1)
            fds = lambda: len(os.listdir(f"/proc/{server.pid}/fd"))
            base, base_kinds = fds(), descriptor_kinds(server.pid)
            for i in range(cycles):
                if problem := cycle(scenes[i % len(scenes)], f"127.0.0.{30 + i % 10}"):
                    return f"cycle {i}: {problem}"
            start = time.monotonic()
            while fds() > base + SPARE_FDS and time.monotonic() - start < 10:
                time.sleep(0.25)
            if fds() <= base + SPARE_FDS:
                return None
            time.sleep(20)
            now = descriptor_kinds(server.pid)
            grew = {k: now.get(k, 0) - base_kinds.get(k, 0) for k in set(now) | set(base_kinds)
                    if now.get(k, 0) != base_kinds.get(k, 0)}
            subprocess.run(f"ls -l /proc/{server.pid}/fd > fds.txt; cat /proc/{server.pid}/task/*/comm | sort | "
                           f"uniq -c > threads.txt; ss -tuanpe | grep 'pid={server.pid},' > sockets.txt",
                           shell=True, cwd=folder)
            return f"kept {fds() - base} descriptors 30 s after (baseline {base}): {grew}"
        finally:
            server.terminate()
            try:
                server.wait(20)
            except subprocess.TimeoutExpired:
                server.kill()
                server.wait()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--causticd", required=True)
    parser.add_argument("--runs", type=int, default=50)
    parser.add_argument("--cycles", type=int, default=20)
    parser.add_argument("--log-level", default="info")
    parser.add_argument("--folder", help="where runs that kept descriptors stay (default: a new temporary one)")
    args = parser.parse_args()
    if args.runs < 1 or args.cycles < 1:
        parser.error("--runs and --cycles must be at least 1")
    root = args.folder or tempfile.mkdtemp(prefix="fresh-server-cycles-")
    kept = released = 0
    for run in range(args.runs):
        folder = f"{root}/run{run}"
        verdict = one_run(args.causticd, folder, args.cycles, args.log_level)
        if verdict and verdict.startswith("the server did not start"):
            print(f"run {run}: {verdict}", file=sys.stderr)
            return 2
        with open(folder + "/stderr.log") as f:
            said = [line.strip() for line in f if "held themselves" in line]
        released += len(said)
        print(f"run {run}: {verdict or 'back at the baseline'}" + "".join("\n  " + s for s in said), flush=True)
        if verdict:
            kept += verdict.startswith("kept")
        elif not said:
            shutil.rmtree(folder)
    if not os.listdir(root):
        os.rmdir(root)
    print(f"{args.runs} runs of {args.cycles} cycles: {kept} kept descriptors, {released} receive bins released" +
          (f"; runs worth reading stay in {root}" if os.path.isdir(root) else ""))
    return 1 if kept else 0


if __name__ == "__main__":
    sys.exit(main())
