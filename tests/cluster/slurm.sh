# shellcheck shell=bash
# slurm.sh: a one-node Slurm cluster on 127.0.0.1 for tests (docs/cluster.md, "A one-node
# Slurm for testing"). Sourced, not run: CMake registers only tests/cluster/test_*.sh.
#
#   . tests/cluster/slurm.sh
#   slurm_available_or_skip             # or exits 77, printing one line saying why it did not run
#   trap slurm_down EXIT
#   slurm_up "$(mktemp -d /tmp/fovsim-slurm.XXXXXX)"   # exports SLURM_CONF; node idle on return
#   sbatch --wait ...                   # or: job=$(sbatch --parsable ...); slurm_wait "$job"
#   slurm_down; [ -z "$(slurm_leftovers)" ]   # the test may check that nothing is left
#
# Everything lives under the folder given to slurm_up: slurm.conf, munge key and socket, state,
# spool, pid and log files. No systemd, no /etc, no default ports. Call slurm_up in the test's own
# shell (not in $(...) or a pipeline): slurm_down stops the daemons by the PIDs it recorded.
# Environment:
#   SLURM_TEST_AUTH     munge (default) or none (AuthType=auth/none: no munged, but no
#                       authentication either, see _slurm_auth)
#   SLURM_TEST_TIMEOUT  seconds slurm_up may take until the node is idle (default 30)
#   SLURM_TEST_TASK_PLUGIN  task/none (default: a task sees every CPU of the node, `nproc` = all)
#                       or task/affinity (a task is bound to the CPUs it was given, as on most
#                       clusters: `nproc` = --cpus-per-task)
#   SLURM_TEST_CONF_EXTRA   further slurm.conf lines, one per line (e.g. "MaxArraySize=5"), for a
#                       test of a cluster's limits; to change them, slurm_down and slurm_up again
# After slurm_up: SLURM_CONF, SLURM_TEST_DIR, SLURM_TEST_NODE, SLURM_TEST_PARTITION.

SLURM_TEST_DIR=
_slurm_pids=()                # munged, slurmctld, slurmd: started here, stopped by slurm_down

# _slurm_bin NAME: the path of a Slurm/munge program; daemons are in /usr/sbin, which a user's
# PATH may lack
_slurm_bin() {
  command -v "$1" 2>/dev/null && return 0
  [ -x "/usr/sbin/$1" ] && { echo "/usr/sbin/$1"; return 0; }
  return 1
}

# _slurm_auth: the authentication to use: munge, unless SLURM_TEST_AUTH=none. The daemons listen on
# every interface (Slurm has no listen address setting), so without munge anyone who reaches the
# ports may run commands as root while the cluster is up: auth/none is never chosen by itself.
_slurm_auth() {
  if [ "${SLURM_TEST_AUTH:-munge}" = none ]; then echo none; else echo munge; fi
}

# slurm_available: 0 when a one-node cluster can be started here; otherwise prints one line saying
# that the Slurm test did not run and why, and returns 1
slurm_available() {
  local p missing=()
  for p in slurmctld slurmd sbatch sinfo squeue scancel scontrol; do
    _slurm_bin "$p" >/dev/null || missing+=("$p")
  done
  if [ "$(_slurm_auth)" = munge ]; then
    for p in munged mungekey munge unmunge; do _slurm_bin "$p" >/dev/null || missing+=("$p"); done
  fi
  if [ ${#missing[@]} -gt 0 ]; then
    echo "slurm: not installed (apt-get install slurmctld slurmd slurm-client munge); the Slurm test did not run"
    return 1
  fi
  if [ "$(id -u)" -ne 0 ]; then
    echo "slurm: needs root (slurmd starts jobs as their owner); the Slurm test did not run"
    return 1
  fi
  return 0
}

# slurm_available_or_skip: for a test's first lines: when slurm_available says no, exits 77
# (ctest: skipped), or 1 under FOVSIM_REQUIRE_SLURM=1 (.ci/run, after installing the packages:
# there a skip would hide a broken installation)
slurm_available_or_skip() {
  slurm_available && return 0
  if [ "${FOVSIM_REQUIRE_SLURM:-0}" = 1 ]; then
    echo "slurm: FOVSIM_REQUIRE_SLURM=1, so that is a failure" >&2
    exit 1
  fi
  exit 77
}

# _slurm_alive PID: the process exists and is not a zombie
_slurm_alive() {
  local s
  { read -r s <"/proc/$1/stat"; } 2>/dev/null || return 1
  s=${s##*) }
  [ "${s%% *}" != Z ]
}

# _slurm_ours PID: the process belongs to this cluster: its environment has our SLURM_CONF (the
# daemons, and through them job steps; jobs, through sbatch)
# (builtins only: a fork costs milliseconds in some VMs, and this runs for every process)
_slurm_ours() {
  local v
  [ -n "$SLURM_TEST_DIR" ] || return 1
  {
    while IFS= read -r -d '' v; do
      [ "$v" = "SLURM_CONF=$SLURM_TEST_DIR/slurm.conf" ] && return 0
    done <"/proc/$1/environ"
  } 2>/dev/null || true
  return 1
}

# slurm_leftovers: prints the PIDs of processes of this cluster still running (daemons, job steps,
# job processes), except this shell and its ancestors. Use as $(slurm_leftovers): in a pipeline
# the other commands, children of this shell with SLURM_CONF in their environment, count too.
slurm_leftovers() {
  local d p skip
  [ -n "$SLURM_TEST_DIR" ] || return 0
  skip=$(_slurm_ancestors)
  for d in /proc/[0-9]*; do
    p=${d#/proc/}
    case "$skip" in *" $p "*) continue ;; esac
    _slurm_ours "$p" && _slurm_alive "$p" && echo "$p"
  done
  return 0
}

# _slurm_ancestors: " PID PID ... ": this shell, its subshell and their ancestors, never to be
# killed (they may carry a SLURM_CONF too)
_slurm_ancestors() {
  local s a=$BASHPID skip=" $$ "
  while [ -n "$a" ] && [ "$a" -gt 1 ]; do
    skip+="$a "
    { read -r s <"/proc/$a/stat"; } 2>/dev/null || break
    s=${s##*) }; s=${s#* }; a=${s%% *}               # field 4, after "pid (comm) state"
  done
  echo "$skip"
}

# _slurm_started PID: the process's start time (clock ticks after boot), or nothing
_slurm_started() {
  local s f
  { read -r s <"/proc/$1/stat"; } 2>/dev/null || return 0
  read -ra f <<<"${s##*) }"                          # from field 3 on: state, ppid, ...
  echo "${f[19]}"                                    # field 22, starttime
}

# _slurm_reap_orphans: SIGKILLs what earlier test clusters left when their test was killed with
# SIGKILL (ctest's timeout kills the test and its children, the daemons, but not the job steps,
# which are no daemon's children; a plain kill -9 of the test leaves the daemons too). A cluster
# is orphaned when the shell that started it (DIR/owner: PID and start time) is gone; then its
# processes are killed: its daemons and job steps, every other process of it whose parent is not
# (an sbatch --wait of the dead test, say), and everything below them.
_slurm_reap_orphans() {
  local d p v s comm conf owner f skip changed
  local -A ppid=() cconf=() daemon=() dead=() doomed=()
  skip=$(_slurm_ancestors)
  for d in /proc/[0-9]*; do
    p=${d#/proc/}
    case "$skip" in *" $p "*) continue ;; esac
    { read -r s <"$d/stat"; } 2>/dev/null || continue
    read -ra f <<<"${s##*) }"
    [ "${f[0]}" != Z ] || continue
    ppid[$p]=${f[1]}
    v=
    {
      while IFS= read -r -d '' v; do
        case "$v" in SLURM_CONF=*) break ;; esac
        v=
      done <"$d/environ"
    } 2>/dev/null || v=                              # another user's process (not as root)
    [ -n "$v" ] || continue
    cconf[$p]=${v#SLURM_CONF=}
    { read -r comm <"$d/comm"; } 2>/dev/null || continue
    case "$comm" in munged|slurmctld|slurmd|slurmstepd) daemon[$p]=1 ;; esac
  done
  for p in "${!cconf[@]}"; do
    conf=${cconf[$p]}
    if [ -z "${dead[$conf]:-}" ]; then
      dead[$conf]=no
      if grep -qx 'ClusterName=fovsimtest' "$conf" 2>/dev/null &&
         { read -r owner s <"${conf%/*}/owner"; } 2>/dev/null &&
         [ "$(_slurm_started "$owner")" != "$s" ]; then
        dead[$conf]=yes
        echo "slurm_up: killing what the cluster of ${conf%/*} left (the shell that started it is gone)" >&2
      fi
    fi
    [ "${dead[$conf]}" = yes ] || continue
    if [ -n "${daemon[$p]:-}" ] || [ "${cconf[${ppid[$p]}]:-}" != "$conf" ]; then doomed[$p]=1; fi
  done
  changed=1                                          # and everything below them
  while [ "$changed" -eq 1 ]; do
    changed=0
    for p in "${!ppid[@]}"; do
      if [ -z "${doomed[$p]:-}" ] && [ -n "${doomed[${ppid[$p]}]:-}" ]; then
        doomed[$p]=1 changed=1
      fi
    done
  done
  [ ${#doomed[@]} -eq 0 ] || kill -KILL "${!doomed[@]}" 2>/dev/null || true
  return 0
}

# _slurm_port_used PORT: some TCP socket (any state) has this local port
_slurm_port_used() {
  local f hex
  hex=$(printf '%04X' "$1")
  for f in /proc/net/tcp /proc/net/tcp6; do
    [ -r "$f" ] || continue
    awk -v h="$hex" 'NR > 1 { split($2, a, ":"); if (a[2] == h) used = 1 } END { exit !used }' "$f" &&
      return 0
  done
  return 1
}

# _slurm_log_tails: the end of every log, for a failed start
_slurm_log_tails() {
  local f
  for f in "$SLURM_TEST_DIR"/log/*; do
    [ -s "$f" ] || continue
    echo "--- $f (last 15 lines)" >&2
    tail -n 15 "$f" >&2
  done
}

_slurm_fail() { echo "slurm_up: $*" >&2; _slurm_log_tails; }

# slurm_up DIR: writes the configuration under DIR, starts munged (unless auth/none), slurmctld and
# slurmd in the background and waits until the node is idle. Exports SLURM_CONF.
slurm_up() {
  local dir=${1:?slurm_up DIR} auth host node nodeline ctld_port d_port i state pid
  local deadline=$((SECONDS + ${SLURM_TEST_TIMEOUT:-30}))
  if [ ${#_slurm_pids[@]} -gt 0 ]; then
    echo "slurm_up: a cluster of this shell is up ($SLURM_TEST_DIR); slurm_down first" >&2
    return 1
  fi
  _slurm_reap_orphans
  mkdir -p "$dir"
  dir=$(cd "$dir" && pwd -P)
  SLURM_TEST_DIR=$dir
  mkdir -p "$dir/state" "$dir/spool" "$dir/log" "$dir/munge"
  auth=$(_slurm_auth)
  if [ "$auth" = munge ]; then
    # munged refuses a socket folder others may write to, and one that not everybody may reach:
    # mode 755 here, and execute permission for all on every folder above (mktemp -d makes 700)
    chmod 755 "$dir" "$dir/munge"
    i=${dir%/*}
    while [ -n "$i" ]; do
      if [ "$(( 0$(stat -c %a "$i") & 1 ))" -eq 0 ]; then
        echo "slurm_up: munged needs execute permission for all on $i (chmod o+x, or another folder)" >&2
        return 1
      fi
      i=${i%/*}
    done
  fi

  # Two free ports, not the defaults 6817/6818 (a real Slurm may run here)
  for i in 1 2 3 4 5 6 7 8 9 10; do
    ctld_port=$((20000 + 2 * (RANDOM % 10000)))
    d_port=$((ctld_port + 1))
    _slurm_port_used "$ctld_port" || _slurm_port_used "$d_port" || break
    [ "$i" -lt 10 ] || { echo "slurm_up: no free port pair found" >&2; return 1; }
  done

  host=$(hostname -s)
  nodeline=$("$(_slurm_bin slurmd)" -C) || { echo "slurm_up: 'slurmd -C' failed" >&2; return 1; }
  nodeline=${nodeline%%$'\n'*}      # NodeName=<host> CPUs=... RealMemory=... (then UpTime=...)
  node=${nodeline%% *}; node=${node#NodeName=}
  [ -n "$node" ] || { echo "slurm_up: 'slurmd -C' printed no node line" >&2; return 1; }
  # Unix socket paths have at most 107 bytes: slurmd's per-step DIR/spool/NODE_JOB.STEP (job and
  # step ids up to 10 digits each) is the longest
  if [ $((${#dir} + ${#node} + 29)) -gt 107 ]; then
    echo "slurm_up: $dir is too long for Slurm's socket paths; use a shorter folder (mktemp -d /tmp/...)" >&2
    return 1
  fi

  {
    echo "# A one-node test cluster on 127.0.0.1 (tests/cluster/slurm.sh)"
    echo "ClusterName=fovsimtest"
    # The host name need not resolve: the address in parentheses is used
    echo "SlurmctldHost=$host(127.0.0.1)"
    echo "SlurmctldPort=$ctld_port"
    echo "SlurmdPort=$d_port"
    if [ "$auth" = munge ]; then
      echo "AuthType=auth/munge"
      echo "CredType=cred/munge"
      echo "AuthInfo=socket=$dir/munge/munge.socket"
    else
      echo "AuthType=auth/none"
      echo "CredType=cred/none"
    fi
    echo "SlurmUser=root"
    echo "SlurmdUser=root"
    echo "StateSaveLocation=$dir/state"
    echo "SlurmdSpoolDir=$dir/spool"
    echo "SlurmctldPidFile=$dir/slurmctld.pid"
    echo "SlurmdPidFile=$dir/slurmd.pid"
    echo "SlurmctldLogFile=$dir/log/slurmctld.log"
    echo "SlurmdLogFile=$dir/log/slurmd.log"
    # No cgroups, no accounting daemon, no mail: nothing outside this folder
    echo "SelectType=select/cons_tres"
    echo "SelectTypeParameters=CR_Core"
    echo "ProctrackType=proctrack/linuxproc"
    echo "TaskPlugin=${SLURM_TEST_TASK_PLUGIN:-task/none}"
    echo "JobAcctGatherType=jobacct_gather/none"
    echo "AccountingStorageType=accounting_storage/none"
    echo "MpiDefault=none"
    echo "MailProg=/bin/true"
    # Start queued batch jobs (array tasks) as soon as CPUs free up, not in 3 s steps
    echo "SchedulerParameters=batch_sched_delay=0"
    # A node that was down comes back by itself when slurmd registers
    echo "ReturnToService=2"
    # NodeAddr: otherwise slurmctld resolves the node name, which may not resolve, and the node
    # stays unreachable
    echo "$nodeline NodeAddr=127.0.0.1 State=UNKNOWN"
    echo "PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP"
    [ -z "${SLURM_TEST_CONF_EXTRA:-}" ] || printf '%s\n' "$SLURM_TEST_CONF_EXTRA"
  } >"$dir/slurm.conf"
  export SLURM_CONF=$dir/slurm.conf
  # Who owns this cluster: _slurm_reap_orphans of a later slurm_up cleans up if it is killed
  pid=$BASHPID
  echo "$pid $(_slurm_started "$pid")" >"$dir/owner"
  # shellcheck disable=SC2034  # for the caller
  SLURM_TEST_NODE=$node SLURM_TEST_PARTITION=test

  # The daemons run in the foreground of background jobs of this shell: $! is their PID, and the
  # environment they inherit (SLURM_CONF) marks them and their job steps as ours
  if [ "$auth" = munge ]; then
    "$(_slurm_bin mungekey)" --create --keyfile="$dir/munge/munge.key" ||
      { echo "slurm_up: mungekey failed" >&2; return 1; }
    "$(_slurm_bin munged)" --foreground --key-file="$dir/munge/munge.key" \
      --socket="$dir/munge/munge.socket" --pid-file="$dir/munge/munged.pid" \
      --log-file="$dir/log/munged.log" --seed-file="$dir/munge/munged.seed" \
      </dev/null >"$dir/log/munged.out" 2>&1 &
    pid=$!
    _slurm_pids+=("$pid")
    # ready when a credential round-trips through the socket
    until "$(_slurm_bin munge)" -S "$dir/munge/munge.socket" -n 2>/dev/null |
        "$(_slurm_bin unmunge)" -S "$dir/munge/munge.socket" >/dev/null 2>&1; do
      _slurm_alive "$pid" || { _slurm_fail "munged exited"; return 1; }
      [ "$SECONDS" -lt "$deadline" ] || { _slurm_fail "munged did not answer in time"; return 1; }
      sleep 0.1
    done
  fi
  "$(_slurm_bin slurmctld)" -D -c -f "$SLURM_CONF" </dev/null >"$dir/log/slurmctld.out" 2>&1 &
  _slurm_pids+=("$!")
  "$(_slurm_bin slurmd)" -D -f "$SLURM_CONF" </dev/null >"$dir/log/slurmd.out" 2>&1 &
  _slurm_pids+=("$!")

  while :; do
    state=$(timeout 5 sinfo -h -N -n "$node" -o %T 2>/dev/null) || state=
    [ "$state" = idle ] && return 0
    for pid in "${_slurm_pids[@]}"; do
      _slurm_alive "$pid" || { _slurm_fail "a daemon exited (pid $pid)"; return 1; }
    done
    [ "$SECONDS" -lt "$deadline" ] || {
      _slurm_fail "node $node not idle after ${SLURM_TEST_TIMEOUT:-30} s (state: ${state:-no answer})"
      return 1
    }
    sleep 0.2
  done
}

# slurm_wait JOBID [SECONDS]: waits until every task of the job (or array) has ended, polling
# every 0.5 s, for at most SECONDS (default 300; then returns 124). Returns what `sbatch --wait`
# would: the highest exit status of the tasks, 1 for a task ended by a signal. Unlike sbatch
# --wait, which polls after 2 s, 10 s, then every 32 s (an 11 s array returns after 42 s), it
# returns within half a second of the end.
slurm_wait() {
  local job=${1:?slurm_wait JOBID} limit=${2:-300} n out rc
  for ((n = 0; n < limit * 2; n++)); do
    if out=$(timeout 5 scontrol -o show job "$job" 2>/dev/null); then
      rc=$(awk '{ for (i = 1; i <= NF; i++) {
                    if ($i ~ /^JobState=/) state = substr($i, 10)
                    if ($i ~ /^ExitCode=/) { split(substr($i, 10), c, ":"); code = c[2] ? 1 : c[1] } }
                  if (state !~ /^(COMPLETED|FAILED|CANCELLED|TIMEOUT|NODE_FAIL|PREEMPTED|BOOT_FAIL|DEADLINE|OUT_OF_MEMORY)$/) {
                    busy = 1; exit }
                  if (code > max) max = code }
                END { print busy ? "busy" : max + 0 }' <<<"$out")
      [ "$rc" = busy ] || return "$rc"
    fi
    sleep 0.5
  done
  echo "slurm_wait: job $job still not done after $limit s" >&2
  return 124
}

# _slurm_stop SECONDS PID...: SIGTERM, then SIGKILL what is left after SECONDS. Every command may
# fail here without ending a caller that runs under set -e.
_slurm_stop() {
  local wait_s=$1 p n left; shift
  [ $# -gt 0 ] || return 0
  kill -TERM "$@" 2>/dev/null || true
  for ((n = 0; n < wait_s * 10; n++)); do
    left=0
    for p in "$@"; do _slurm_alive "$p" && left=1; done
    [ "$left" -eq 0 ] && break
    sleep 0.1
  done
  for p in "$@"; do
    if _slurm_alive "$p"; then
      echo "slurm_down: pid $p ignored SIGTERM for $wait_s s; SIGKILL" >&2
      kill -KILL "$p" 2>/dev/null || true
    fi
  done
  for p in "$@"; do wait "$p" 2>/dev/null || true; done    # reaps our own children
  return 0
}

# slurm_down: cancels the jobs, stops slurmd, slurmctld and munged by the PIDs slurm_up recorded
# (SIGTERM, SIGKILL after 5 s), then SIGKILLs whatever process of this cluster is left (job steps,
# jobs). 30 s at worst; safe more than once, after a failed slurm_up or none. Unsets SLURM_CONF.
slurm_down() {
  local p n left ours=() end=$((SECONDS + 10)) conf=$SLURM_TEST_DIR/slurm.conf
  [ -n "$SLURM_TEST_DIR" ] || return 0
  # What this shell starts from now on no longer names this cluster (slurm_leftovers would count it)
  [ "${SLURM_CONF:-}" != "$conf" ] || unset SLURM_CONF
  # Jobs first, while slurmctld and slurmd can still end their steps (10 s at most; slurmd is the
  # last PID: without it nothing ends, and the leftovers below are killed instead)
  if [ ${#_slurm_pids[@]} -gt 0 ] && _slurm_alive "${_slurm_pids[-1]}"; then
    SLURM_CONF=$conf timeout 5 scancel --quiet --user="$(id -un)" 2>/dev/null || true
    while [ "$SECONDS" -lt "$end" ]; do
      left=$(SLURM_CONF=$conf timeout 2 squeue -h -o %i -u "$(id -un)" 2>/dev/null) || break
      [ -z "$left" ] && break
      sleep 0.2
    done
  fi
  # slurmd first (no new steps), then slurmctld, then munged
  for ((n = ${#_slurm_pids[@]} - 1; n >= 0; n--)); do
    p=${_slurm_pids[n]}
    if _slurm_alive "$p" && _slurm_ours "$p"; then _slurm_stop 5 "$p"; fi
  done
  _slurm_pids=()
  # Job steps (slurmstepd is not slurmd's child) and their jobs, should any have survived
  mapfile -t ours < <(slurm_leftovers)
  if [ ${#ours[@]} -gt 0 ]; then
    echo "slurm_down: SIGKILL to leftover processes ${ours[*]}" >&2
    kill -KILL "${ours[@]}" 2>/dev/null || true
    for ((n = 0; n < 50; n++)); do
      left=0
      for p in "${ours[@]}"; do _slurm_alive "$p" && left=1; done
      [ "$left" -eq 0 ] && break
      sleep 0.1
    done
    for p in "${ours[@]}"; do wait "$p" 2>/dev/null || true; done
  fi
  return 0
}
