#!/usr/bin/env bash
# A single-node Slurm cluster on this machine (localhost), from Debian's packages, for
# trying the job array of this directory. Run as root; idempotent (a cluster already up is
# left as it is).
#
#   sudo examples/slurm/setup_single_node.sh            # install, configure, start
#   SLURM_INSTALL=0 examples/slurm/setup_single_node.sh # packages already installed
#
# What it does: installs slurm-wlm and munge (apt-get), creates the munge key if missing,
# starts munged, writes /etc/slurm/slurm.conf for one node (this host, NodeAddr 127.0.0.1,
# its CPUs and memory as `slurmd -C` reports them, one partition `debug`), starts slurmctld
# and slurmd, and waits until the node is idle. In a container (no systemd, no cgroups) it
# uses ProctrackType=proctrack/linuxproc, TaskPlugin=task/none and
# JobAcctGatherType=jobacct_gather/none. Logs: /var/log/slurm/.
set -euo pipefail

if [ "$(id -u)" != 0 ]; then
    echo "setup_single_node.sh: run as root" >&2
    exit 2
fi

if sinfo -h -o '%T' 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then
    echo "slurm: already up ($(sinfo -h -o '%N %T' | head -1))"
    exit 0
fi

if [ "${SLURM_INSTALL:-1}" = 1 ] && ! command -v slurmctld >/dev/null; then
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -q
    apt-get install -y -q --no-install-recommends slurm-wlm munge
fi

# munge: a key, then the daemon as the munge user.
if [ ! -s /etc/munge/munge.key ]; then
    if command -v mungekey >/dev/null; then mungekey --create --force; else create-munge-key -f; fi
fi
chown munge:munge /etc/munge/munge.key
chmod 400 /etc/munge/munge.key
mkdir -p /run/munge /var/log/munge /var/lib/munge
chown munge:munge /run/munge /var/log/munge /var/lib/munge
if ! pgrep -u munge -x munged >/dev/null; then
    runuser -u munge -- /usr/sbin/munged
fi
munge -n | unmunge >/dev/null

# slurm.conf for this one node.
host=$(hostname -s)
node=$(slurmd -C | head -1 | sed -e "s/^NodeName=[^ ]*/NodeName=$host NodeAddr=127.0.0.1/")
mkdir -p /etc/slurm /var/lib/slurm/slurmctld /var/lib/slurm/slurmd /var/log/slurm /run/slurm
cat > /etc/slurm/slurm.conf <<CONF
# Single-node cluster on localhost (examples/slurm/setup_single_node.sh).
ClusterName=drystone
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
AuthType=auth/munge
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
StateSaveLocation=/var/lib/slurm/slurmctld
SlurmdSpoolDir=/var/lib/slurm/slurmd
SlurmctldPidFile=/run/slurm/slurmctld.pid
SlurmdPidFile=/run/slurm/slurmd.pid
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
$node State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF

pgrep -x slurmctld >/dev/null || slurmctld
pgrep -x slurmd >/dev/null || slurmd
for _ in $(seq 1 60); do
    state=$(sinfo -h -o '%T' 2>/dev/null | head -1 || true)
    case "$state" in
        idle|mixed|allocated) echo "slurm: node $host $state"; exit 0 ;;
        down*|drain*) scontrol update nodename="$host" state=resume 2>/dev/null || true ;;
    esac
    sleep 1
done
echo "setup_single_node.sh: the node did not come up; see /var/log/slurm/" >&2
exit 1
