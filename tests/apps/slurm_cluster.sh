# A throwaway single-node Slurm cluster on localhost for the tests, sourced by a test script.
#   slurm_start DIR  starts munged, slurmctld and slurmd with everything they write under DIR
#                    (key, socket, config, state, spool, logs, pid files), exports SLURM_CONF
#                    for sbatch/squeue/scancel, and returns 0 once the node is idle; otherwise
#                    it prints one line on stderr and returns 1 (also when the binaries are
#                    missing, so that the caller can skip).
#                    SLURM_EXTRA_CONF, when set, holds more slurm.conf lines.
#   slurm_stop       cancels the cluster's jobs and kills the daemons that slurm_start started.
# Needs root (SlurmUser=root), no systemd, no writable cgroup and nothing from /etc.
slurm_cluster_dir=

# _slurm_port_free PORT: no TCP socket on this machine is bound to PORT (IPv4 or IPv6).
_slurm_port_free() {
  local f hex
  hex=$(printf ':%04X$' "$1")
  for f in /proc/net/tcp /proc/net/tcp6; do
    [[ -r $f ]] && awk -v p="$hex" '$2 ~ p {f = 1} END {exit !f}' "$f" && return 1
  done
  return 0
}

# _slurm_pick_port: a free port in 20000-59999 that is not in $_slurm_taken.
_slurm_pick_port() {
  local p i
  for ((i = 0; i < 200; i++)); do
    p=$((20000 + RANDOM % 40000))
    if [[ " ${_slurm_taken-} " != *" $p "* ]] && _slurm_port_free "$p"; then
      echo "$p"
      return 0
    fi
  done
  return 1
}

slurm_start() {
  local dir=${1:?slurm_start: directory expected} b
  for b in munged mungekey slurmctld slurmd sinfo sbatch squeue scancel scontrol; do
    if ! command -v "$b" >/dev/null 2>&1 && [[ ! -x /usr/sbin/$b ]]; then
      echo "slurm_start: $b not found (install slurm-wlm and munge)" >&2
      return 1
    fi
  done
  [[ :$PATH: == *:/usr/sbin:* ]] || PATH=$PATH:/usr/sbin
  [[ -z ${slurm_cluster_dir:-} ]] || slurm_stop
  mkdir -p "$dir" && dir=$(cd "$dir" && pwd) || return 1
  [[ $dir != *[[:space:]]* ]] || { echo "slurm_start: no blanks allowed in '$dir'" >&2; return 1; }
  # The socket's folder must be searchable by all, the key itself is private (0600).
  mkdir -p "$dir/munge" "$dir/state" "$dir/spool" "$dir/log" && chmod 755 "$dir/munge" || return 1
  slurm_cluster_dir=$dir

  # munged: its own key, socket, pid, log and seed files; --force because it runs as root.
  local sock=$dir/munge/munge.socket
  mungekey --create --keyfile="$dir/munge/munge.key" --force 2>"$dir/log/mungekey.log" ||
    { echo "slurm_start: mungekey failed: $(tail -n 1 "$dir/log/mungekey.log")" >&2; return 1; }
  if ! munged --force --socket="$sock" --key-file="$dir/munge/munge.key" \
      --pid-file="$dir/munge/munged.pid" --log-file="$dir/log/munged.log" \
      --seed-file="$dir/munge/munged.seed" </dev/null >"$dir/log/munged.out" 2>&1; then
    echo "slurm_start: munged failed: $(tail -n 1 "$dir/log/munged.out")" >&2
    return 1
  fi

  local node cpus mem ctld_port slurmd_port _slurm_taken=
  node=$(hostname -s)
  cpus=$(nproc)
  mem=$(slurmd -C 2>/dev/null | sed -n 's/.*RealMemory=\([0-9]*\).*/\1/p') || mem=
  ctld_port=$(_slurm_pick_port) && _slurm_taken=$ctld_port && slurmd_port=$(_slurm_pick_port) ||
    { echo "slurm_start: no free TCP port found" >&2; slurm_stop; return 1; }
  : >"$dir/plugstack.conf"
  # slurm.conf takes one setting a line (hence tr): everything under DIR, munge on its own
  # socket, no cgroups, no accounting database, short timeouts, finished jobs kept for 300 s.
  tr ' ' '\n' >"$dir/slurm.conf" <<EOF
ClusterName=testcluster SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port SlurmdPort=$slurmd_port
AuthType=auth/munge CredType=cred/munge AuthInfo=socket=$sock
SlurmUser=root SlurmdUser=root
StateSaveLocation=$dir/state SlurmdSpoolDir=$dir/spool PlugStackConfig=$dir/plugstack.conf
SlurmctldPidFile=$dir/slurmctld.pid SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdPidFile=$dir/slurmd.pid SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc TaskPlugin=task/none JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none JobCompType=jobcomp/none MailProg=/bin/true
SelectType=select/cons_tres SelectTypeParameters=CR_CPU SchedulerType=sched/backfill
MpiDefault=none ReturnToService=2
SlurmctldTimeout=30 SlurmdTimeout=30 MessageTimeout=5 KillWait=5 InactiveLimit=0 MinJobAge=300
EOF
  cat >>"$dir/slurm.conf" <<EOF
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus${mem:+ RealMemory=$((mem * 9 / 10))} State=UNKNOWN
PartitionName=debug Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
  # More settings from the caller, one a line (e.g. MaxArraySize=5).
  [[ -z ${SLURM_EXTRA_CONF-} ]] || printf '%s\n' "$SLURM_EXTRA_CONF" >>"$dir/slurm.conf"
  export SLURM_CONF=$dir/slurm.conf

  # Both daemons in the foreground (-D), in the background of this shell, output to the logs.
  slurmctld -D -i -f "$SLURM_CONF" </dev/null >"$dir/log/slurmctld.out" 2>&1 &
  echo $! >"$dir/slurmctld.bgpid"
  slurmd -D -N "$node" -f "$SLURM_CONF" </dev/null >"$dir/log/slurmd.out" 2>&1 &
  echo $! >"$dir/slurmd.bgpid"

  # Wait (60 s at most) for the node to be idle; resume it if it comes up down or drained.
  local state='' end=$((SECONDS + 60))
  while ((SECONDS < end)); do
    state=$(sinfo -h -n "$node" -o %T 2>/dev/null | head -n 1) || state=
    case $state in
      idle) return 0 ;;
      down* | drain*) scontrol update nodename="$node" state=resume >/dev/null 2>&1 || true ;;
    esac
    for b in slurmctld slurmd; do
      if ! kill -0 "$(cat "$dir/$b.bgpid")" 2>/dev/null; then
        echo "slurm_start: $b exited: $(cat "$dir/log/$b.log" "$dir/log/$b.out" 2>/dev/null | grep -E 'error|fatal' | tail -n 1)" >&2
        slurm_stop
        return 1
      fi
    done
    sleep 0.5
  done
  echo "slurm_start: node $node not idle after 60 s (state '${state:-none}'), see $dir/log" >&2
  slurm_stop
  return 1
}

slurm_stop() {
  local dir=${slurm_cluster_dir:-} f pid c i
  [[ -n $dir ]] || return 0
  # Cancel the jobs first so that their steps are killed (TERM, KILL after KillWait), 10 s at most.
  if kill -0 "$(cat "$dir/slurmctld.bgpid" 2>/dev/null)" 2>/dev/null; then
    SLURM_CONF=$dir/slurm.conf scancel --quiet --user="$(id -un)" >/dev/null 2>&1 || true
    for ((i = 0; i < 20; i++)); do
      [[ -z $(SLURM_CONF=$dir/slurm.conf squeue -h -t R,CG,S -o %i 2>/dev/null) ]] && break
      sleep 0.5
    done
  fi
  # Then the daemons: TERM, up to 10 s, then KILL.
  for f in slurmd.bgpid slurmctld.bgpid munge/munged.pid; do
    pid=$(cat "$dir/$f" 2>/dev/null) || continue
    # Only if it is still ours (its command line names DIR): the number may have been reused.
    grep -qF "$dir/" "/proc/$pid/cmdline" 2>/dev/null && kill "$pid" 2>/dev/null || continue
    for ((i = 0; i < 20; i++)); do
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.5
    done
    kill -9 "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
  done
  # Any step daemon of this cluster still there (its environment names this SLURM_CONF), with
  # the process groups of the job scripts it started.
  for pid in $(pgrep -x slurmstepd || true); do
    if grep -qzxF "SLURM_CONF=$dir/slurm.conf" "/proc/$pid/environ" 2>/dev/null; then
      for c in $(pgrep -P "$pid" || true); do kill -9 -- "-$c" "$c" 2>/dev/null || true; done
      kill -9 "$pid" 2>/dev/null || true
    fi
  done
  slurm_cluster_dir=
  return 0
}
