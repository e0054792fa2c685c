#!/bin/bash
# A one-node Slurm cluster on this machine (Debian's slurm-wlm: munge, slurmctld and
# slurmd, all as root), for trying the job-array recipe without a cluster; the shard
# test (models/tests/shards.rs) submits a real array job when `sinfo` answers.
#
#   apt-get install -y slurm-wlm && bash docs/recipes/slurm-one-node.sh
#
# It writes /etc/slurm/slurm.conf (one node, one partition `debug`) and a munge key if
# there is none. Not for a shared machine: it runs the daemons as root.
set -e
H=$(hostname -s)
CPUS=$(nproc)
MEM=$(( $(awk '/MemTotal/{print $2}' /proc/meminfo) / 1024 / 2 ))
mkdir -p /etc/slurm /var/spool/slurmctld /var/spool/slurmd /var/log/slurm /run/munge
[ -f /etc/munge/munge.key ] || (dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key 2>/dev/null)
chown munge:munge /etc/munge/munge.key /run/munge; chmod 400 /etc/munge/munge.key
chown slurm:slurm /var/spool/slurmctld /var/log/slurm || true
cat > /etc/slurm/slurm.conf <<CONF
ClusterName=bgdsl
SlurmctldHost=$H
SlurmUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
ReturnToService=2
MpiDefault=none
NodeName=$H CPUs=$CPUS RealMemory=$MEM State=UNKNOWN
PartitionName=debug Nodes=$H Default=YES MaxTime=INFINITE State=UP OverSubscribe=FORCE
CONF
pgrep -x munged >/dev/null || munged --force
pgrep -x slurmctld >/dev/null || slurmctld
pgrep -x slurmd >/dev/null || slurmd
sleep 3
sinfo
