"""A one-node Slurm 22.05 cluster for tests, started and stopped
by the caller inside a private network namespace:

  with SlurmCluster(workdir) as cl:      # munged, slurmctld, slurmd
      env = cl.env                       # SLURM_CONF for sbatch/squeue/...

Run it as root in a process that `unshare -n` started (the test re-executes
itself so): `lo` is brought up with a second address, 127.0.0.2, for the
daemons (their address lookup ignores a lone 127.0.0.1). No accounting, no
cgroups: ProctrackType=proctrack/linuxproc, TaskPlugin=task/none. Every
daemon is started in the foreground and stopped by its process id; on stop,
any process still naming the cluster's folder (a job step, slurmstepd) is
reported and stopped by its id too."""
import os
import signal
import socket
import subprocess
import sys
import time

NODE_ADDR = "127.0.0.2"


def tools_missing():
    """The names of the slurm-wlm / munge programs not installed."""
    need = ["/usr/sbin/munged", "/usr/sbin/slurmctld", "/usr/sbin/slurmd", "/usr/sbin/slurmstepd"]
    missing = [p for p in need if not os.access(p, os.X_OK)]
    for p in ["sbatch", "squeue", "scontrol", "sinfo"]:
        if not any(os.access(os.path.join(d, p), os.X_OK) for d in os.environ.get("PATH", "").split(":")):
            missing.append(p)
    return missing


def setup_loopback():
    subprocess.run(["ip", "link", "set", "lo", "up"], check=True)
    subprocess.run(["ip", "addr", "add", NODE_ADDR + "/8", "dev", "lo"], check=True)


class SlurmCluster:
    def __init__(self, workdir, cpus=None):
        self.dir = os.path.abspath(workdir)
        self.cpus = cpus or os.cpu_count() or 1
        self.procs = []
        self.leftovers = []
        self.host = socket.gethostname()
        self.conf = os.path.join(self.dir, "slurm.conf")
        self.env = dict(os.environ, SLURM_CONF=self.conf)

    def _write_conf(self):
        d = self.dir
        for sub in ("state", "spool", "log", "munge"):
            os.makedirs(os.path.join(d, sub), exist_ok=True)
        os.chmod(os.path.join(d, "munge"), 0o700)
        key = os.path.join(d, "munge", "munge.key")
        with open(key, "wb") as f:
            f.write(os.urandom(1024))
        os.chmod(key, 0o400)
        self.munge_socket = os.path.join(d, "munge", "munge.socket")
        conf = f"""ClusterName=pbtest
SlurmctldHost={self.host}({NODE_ADDR})
MailProg=/bin/true
SlurmUser=root
SlurmdUser=root
SlurmctldPort=6817
SlurmdPort=6818
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={self.munge_socket}
StateSaveLocation={d}/state
SlurmdSpoolDir={d}/spool
SlurmctldPidFile={d}/slurmctld.pid
SlurmdPidFile={d}/slurmd.pid
SlurmctldLogFile={d}/log/slurmctld.log
SlurmdLogFile={d}/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SlurmdParameters=config_overrides
ReturnToService=2
SchedulerParameters=sched_interval=1
MessageTimeout=20
KillWait=2
InactiveLimit=0
MinJobAge=300
SlurmctldTimeout=30
SlurmdTimeout=60
NodeName=pbnode NodeHostname={self.host} NodeAddr={NODE_ADDR} CPUs={self.cpus} State=UNKNOWN
PartitionName=pb Nodes=pbnode Default=YES MaxTime=INFINITE State=UP
"""
        with open(self.conf, "w") as f:
            f.write(conf)

    def _start(self, name, args):
        log = open(os.path.join(self.dir, "log", name + ".out"), "w")
        p = subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT, env=self.env, cwd=self.dir)
        log.close()
        self.procs.append((name, p))
        return p

    def start(self, timeout=40):
        self._write_conf()
        d = self.dir
        self._start("munged", ["/usr/sbin/munged", "-F", "--force", "--socket=" + self.munge_socket,
                               "--key-file=" + os.path.join(d, "munge", "munge.key"),
                               "--pid-file=" + os.path.join(d, "munge", "munged.pid"),
                               "--log-file=" + os.path.join(d, "log", "munged.log"),
                               "--seed-file=" + os.path.join(d, "munge", "munged.seed")])
        t0 = time.time()
        while not os.path.exists(self.munge_socket):
            self._alive_or_raise()
            if time.time() - t0 > 10:
                raise RuntimeError("munged: no socket after 10 s")
            time.sleep(0.1)
        self._start("slurmctld", ["/usr/sbin/slurmctld", "-D", "-i", "-f", self.conf])
        self._start("slurmd", ["/usr/sbin/slurmd", "-D", "-N", "pbnode", "-f", self.conf])
        while True:
            self._alive_or_raise()
            p = subprocess.run(["sinfo", "-h", "-n", "pbnode", "-o", "%t"], env=self.env,
                               capture_output=True, text=True)
            state = p.stdout.strip()
            if p.returncode == 0 and state in ("idle", "mix", "alloc"):
                return
            if time.time() - t0 > timeout:
                raise RuntimeError("slurm: node not idle after %d s (sinfo: %r %r)" %
                                   (timeout, state, p.stderr.strip()[-300:]))
            time.sleep(0.5)

    def _alive_or_raise(self):
        for name, p in self.procs:
            if p.poll() is not None:
                tail = ""
                try:
                    tail = open(os.path.join(self.dir, "log", name + ".out")).read()[-1500:]
                except OSError:
                    pass
                raise RuntimeError("%s exited (%s): %s" % (name, p.returncode, tail))

    def _strays(self):
        """Processes (not ours to keep) whose command line or environment
        names the cluster's folder: job steps and slurmstepd."""
        out = []
        me = os.getpid()
        ours = {p.pid for _, p in self.procs}
        needle = self.dir.encode()
        for e in os.listdir("/proc"):
            if not e.isdigit() or int(e) in ours or int(e) == me:
                continue
            try:
                with open("/proc/%s/cmdline" % e, "rb") as f:
                    cmd = f.read()
                with open("/proc/%s/environ" % e, "rb") as f:
                    env = f.read()
            except OSError:
                continue
            if needle in cmd or (b"SLURM_CONF=" + needle) in env:
                out.append((int(e), cmd.replace(b"\0", b" ").decode(errors="replace")[:200]))
        return out

    def stop(self):
        # slurmd first (it ends its steps), then slurmctld, then munged.
        for name, p in reversed(self.procs):
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
                try:
                    p.wait(15)
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait()
        self.leftovers = self._strays()
        for pid, _ in self.leftovers:
            try:
                os.kill(pid, signal.SIGKILL)
            except OSError:
                pass
        self.procs = []

    def __enter__(self):
        try:
            self.start()
        except BaseException:
            self.stop()
            raise
        return self

    def __exit__(self, *exc):
        self.stop()
        return False


def enter_netns(script, device_ok):
    """The farm tests' prologue outside the namespace: exit 77 with one line
    where the cluster cannot run (slurm-wlm/munge missing, not root, no
    `unshare -n`, no Vulkan device), else run `script` again inside a
    private network namespace (PB_FARM_NETNS=1) and exit with its status."""
    def skip(msg):
        print("skip: " + msg)
        sys.exit(77)
    missing = tools_missing()
    if missing:
        skip("slurm-wlm/munge not installed (%s); scripts/install-deps.sh installs them" % " ".join(missing))
    if os.geteuid() != 0:
        skip("the one-node Slurm cluster needs root (its daemons run as root)")
    if subprocess.run(["unshare", "-n", "true"], capture_output=True).returncode != 0:
        skip("network namespaces not permitted here (unshare -n failed)")
    if not device_ok:
        skip("no Vulkan device")
    env = dict(os.environ, PB_FARM_NETNS="1")
    sys.exit(subprocess.run(["unshare", "-n", sys.executable, os.path.abspath(script)] + sys.argv[1:],
                            env=env).returncode)
