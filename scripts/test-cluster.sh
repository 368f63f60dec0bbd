#!/usr/bin/env bash
# A real cluster run on this machine: starts a one-node Slurm (Debian slurm-wlm and munge, for
# localhost, as root), runs workflows/Snakefile through it with the profile
# workflows/profiles/slurm on a survey of four LAZ files, runs the same workflow locally, and
# checks that the two give the same bytes (OUT/splats.splk, model.spt, model.qs, the tiles). Stops
# what it started and removes its files, however it ends.
# usage: scripts/test-cluster.sh [BUILD_DIR]   (root; installs slurm-wlm, munge, snakemake when
#        missing; BUILD_DIR defaults to build, built first)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
[ "$(id -u)" -eq 0 ] || { echo "test-cluster.sh: run as root (it starts slurmctld, slurmd, munged)" >&2; exit 1; }
missing=()
for p in slurm-wlm munge snakemake; do
  [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)" = "install ok installed" ] || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
ninja -C "$build" -j2 >/dev/null
bin=$build/tools
work=$(mktemp -d /tmp/splatkit-cluster.XXXXXX)
chmod 755 "$work"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  [ -f "$work/munged.pid" ] && kill "$(cat "$work/munged.pid")" 2>/dev/null || true
  sleep 1
  [ -n "${KEEP_WORK:-}" ] && echo "kept $work" >&2 || rm -rf "$work"
}
trap cleanup EXIT

# munge: a key of our own and a daemon on a socket of our own.
mkdir -p "$work/munge"
chown munge: "$work/munge" 2>/dev/null || true
dd if=/dev/urandom bs=1 count=1024 of="$work/munge/munge.key" status=none
chown munge: "$work/munge/munge.key" && chmod 400 "$work/munge/munge.key"
runuser -u munge -- munged --key-file="$work/munge/munge.key" --socket="$work/munge/socket" \
  --pid-file="$work/munged.pid" --log-file="$work/munge/munged.log" --seed-file="$work/munge/seed"
export MUNGE_SOCKET="$work/munge/socket"

# Slurm: one node (this machine), every core, one partition; no accounting, no cgroups.
host=$(hostname -s)
cpus=$(nproc)
mem=$(awk '/MemTotal/ { print int($2 / 1024 * 0.9) }' /proc/meminfo)
mkdir -p "$work/slurm/state" "$work/slurm/spool"
cat >"$work/slurm/slurm.conf" <<CONF
ClusterName=splatkit
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge/socket
CredType=cred/munge
StateSaveLocation=$work/slurm/state
SlurmdSpoolDir=$work/slurm/spool
SlurmctldPidFile=$work/slurm/slurmctld.pid
SlurmdPidFile=$work/slurm/slurmd.pid
SlurmctldLogFile=$work/slurm/slurmctld.log
SlurmdLogFile=$work/slurm/slurmd.log
SlurmctldPort=16817
SlurmdPort=16818
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=main Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm/slurm.conf
slurmctld -D -f "$SLURM_CONF" >"$work/slurm/ctld.out" 2>&1 & pids+=($!)
slurmd -D -f "$SLURM_CONF" >"$work/slurm/d.out" 2>&1 & pids+=($!)
for _ in $(seq 60); do
  sinfo -h -o %T 2>/dev/null | grep -qx idle && break
  sleep 1
done
sinfo -h -o %T | grep -qx idle || {
  echo "test-cluster.sh: the node did not come up:" >&2
  tail -5 "$work/slurm/slurmctld.log" "$work/slurm/slurmd.log" >&2
  exit 1
}
echo "test-cluster.sh: Slurm up: $(sinfo -h -o '%P %D nodes %c CPUs %T')"

# The survey: a CAD part and a torus (i.i.d. samples) in four LAZ files cut along slanted lines.
cd "$work"
"$root/scripts/make-test-survey.sh" "$work" "$bin" 100000
config=(input="$work/scans/*.laz" tile_size=12 bin="$bin" threads=1)
t0=$(date +%s.%N)
snakemake -s "$root/workflows/Snakefile" --profile "$root/workflows/profiles/slurm" -q \
  --config "${config[@]}" outdir="$work/out" >slurm-run.log 2>&1 ||
  { tail -20 slurm-run.log >&2; exit 1; }
t1=$(date +%s.%N)
# (The same output folder for both runs: the files record the paths of their inputs.)
mv out slurm-out
submitted=$(find .snakemake -maxdepth 1 -name 'slurm-*.log' | wc -l)  # one log per Slurm job
snakemake -s "$root/workflows/Snakefile" --cores "$cpus" -q --config "${config[@]}" \
  outdir="$work/out" >local-run.log 2>&1 || { tail -20 local-run.log >&2; exit 1; }
t2=$(date +%s.%N)
mv out local-out
status=0
for f in splats.splk model.spt model.qs tiled/tiles.json; do
  if cmp -s "slurm-out/$f" "local-out/$f"; then
    echo "same: $f ($(stat -c %s "local-out/$f") bytes)"
  else
    echo "DIFFERENT: $f" >&2; status=1
  fi
done
for f in local-out/surfaces/*.splk; do
  cmp -s "$f" "slurm-out/surfaces/$(basename "$f")" || { echo "DIFFERENT: $f" >&2; status=1; }
done
jobs=$(jq '.jobs | length' slurm-out/report.json)
printf 'test-cluster.sh: %s jobs through Slurm (%s Slurm job logs) in %.1f s, locally in %.1f s; CPU: %s\n' \
  "$jobs" "$submitted" "$(echo "$t1 - $t0" | bc)" "$(echo "$t2 - $t1" | bc)" \
  "$(lscpu | sed -n 's/^Model name: *//p')"
[ "$status" -eq 0 ] && echo "test-cluster.sh: passed" || echo "test-cluster.sh: FAILED" >&2
exit "$status"
