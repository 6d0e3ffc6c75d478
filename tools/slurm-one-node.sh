#!/usr/bin/env bash
# Starts a one-node Slurm cluster on this machine from Debian's packages
# (slurm-wlm, munge), so that the tests can send a portfolio's jobs through
# future.batchtools' Slurm back-end as a cluster would. For CI and
# developers' machines, not for a real cluster: it writes
# /etc/slurm/slurm.conf only where none exists or where it wrote it before,
# and refuses otherwise. Needs root (or sudo). Safe to run again: daemons
# already answering are left as they are. Ends when `sinfo` shows the node
# idle, or fails saying which daemon did not start.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
marker="# written by bayesbem's tools/slurm-one-node.sh"
conf=/etc/slurm/slurm.conf

if ! command -v slurmctld > /dev/null || ! command -v munged > /dev/null; then
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
    slurm-wlm munge > /dev/null
fi

if [ -e "$conf" ] && ! grep -qF "$marker" "$conf"; then
  echo "slurm-one-node: $conf exists and is not this script's; a real cluster is left alone" >&2
  exit 1
fi

# munge authenticates Slurm's messages; its key is made by the package
$SUDO mkdir -p /run/munge
$SUDO chown munge:munge /run/munge
if ! munge -n > /dev/null 2>&1; then
  if [ -z "$SUDO" ]; then runuser -u munge -- /usr/sbin/munged; else sudo -u munge /usr/sbin/munged; fi
fi

# the node as slurmd sees it (CPUs, memory), no cgroups (containers lack
# them): processes tracked by their parents, tasks not bound to cores
node="$(slurmd -C | head -n 1)"
host="$(hostname -s)"
$SUDO mkdir -p /etc/slurm /var/spool/slurmctld /var/spool/slurmd /var/log/slurm
wanted="$(mktemp)"
trap 'rm -f "$wanted"' EXIT
cat > "$wanted" <<EOF
$marker
ClusterName=bayesbem
SlurmctldHost=$host
SlurmUser=root
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
$node State=UNKNOWN
PartitionName=main Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF

# a configuration changed since the daemons started: restart them on it
# (pgrep: living daemons only; a container may leave their forks as zombies)
if ! cmp -s "$wanted" "$conf"; then
  $SUDO cp "$wanted" "$conf"
  $SUDO chmod 644 "$conf"
  if pgrep -x -r S,R,D slurmctld > /dev/null; then $SUDO scontrol shutdown > /dev/null; sleep 2; fi
fi
if ! pgrep -x -r S,R,D slurmctld > /dev/null; then $SUDO slurmctld; fi
if ! pgrep -x -r S,R,D slurmd > /dev/null; then $SUDO slurmd; fi

for _ in $(seq 1 30); do
  state="$(sinfo -h -n "$host" -o %t 2> /dev/null || true)"
  if [ "$state" = "idle" ] || [ "$state" = "mix" ] || [ "$state" = "alloc" ]; then
    echo "slurm-one-node: node $host is $state"
    exit 0
  fi
  sleep 1
done
echo "slurm-one-node: the node did not come up (state '${state:-none}'); see /var/log/slurm/" >&2
exit 1
