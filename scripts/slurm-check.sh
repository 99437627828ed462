#!/usr/bin/env bash
# The Snakemake workflow on a real Slurm cluster of one node, against a local run of the same sessions.
#
#   scripts/slurm-check.sh [BIN]        (BIN: the toolinc executables, default build/bin)
#
# Starts, from Debian's packages and under a scratch folder of its own (nothing of the system's is used or
# changed): munge, MariaDB, slurmdbd (the accounting a real cluster has, which snakemake's Slurm executor
# needs), slurmctld and slurmd on this machine. Then:
#   1. simulates a handful of sessions and runs scripts/Snakefile locally (--cores 2);
#   2. runs it again through --profile scripts/slurm, as shipped (the account and partition are the
#      cluster's defaults for the user), killing snakemake once the first session is done and running
#      the same command again, which must redo only what is missing;
#   3. checks that every output file and summary.csv are byte-identical to the local run's.
# Everything it started is stopped, by process id, whatever happens; the scratch folder is removed
# unless KEEP=1. Needs root (slurmd runs jobs as their user); run through sudo otherwise. Installs the
# packages it needs (slurm-wlm slurmdbd mariadb-server munge) when they are missing. Bounded: each wait
# gives up after a stated time, and the whole check after TIMEOUT seconds (default 900). TRACE=1 traces
# every command.
set -euo pipefail
[ "${TRACE:-0}" = 1 ] && set -x
cd "$(dirname "$0")/.."
ROOT=$PWD
BIN=$(realpath "${1:-build/bin}")
TIMEOUT=${TIMEOUT:-900}

if [ "$(id -u)" -ne 0 ]; then
  exec sudo -E "$0" "$@"
fi
# The packages' own services are not used: every daemon below runs from our folder, on ports of its own.
scripts/install-deps.sh slurm-wlm slurmdbd mariadb-server munge

WORK=$(mktemp -d /tmp/toolinc-slurm.XXXXXX)
chmod 755 "$WORK"
pids=()
stop_all() {
  local status=$?
  set +e
  if [ -n "${SLURM_CONF:-}" ] && [ -f "$SLURM_CONF" ]; then scancel --full --quiet -u "$(id -un)" 2>/dev/null; fi
  # Last started, first stopped, each before the next (slurmdbd still writes to MariaDB as it stops).
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    kill "${pids[i]}" 2>/dev/null
    for _ in $(seq 100); do kill -0 "${pids[i]}" 2>/dev/null || break; sleep 0.1; done
    kill -9 "${pids[i]}" 2>/dev/null
  done
  if [ $status -ne 0 ]; then
    echo "slurm-check: FAILED; the daemons' logs:" >&2
    for log in "$WORK"/log/*.log; do echo "--- $log" >&2; tail -n 20 "$log" >&2; done
  fi
  if [ "${KEEP:-0}" = 1 ]; then echo "slurm-check: kept $WORK" >&2; else rm -rf "$WORK"; fi
  exit $status
}
trap stop_all EXIT
trap 'echo "slurm-check: gave up after $TIMEOUT s" >&2; exit 124' ALRM
# The watchdog holds no output open (a pipe reading ours would wait for it) and takes its sleep with it.
watchdog() {
  sleep "$TIMEOUT" &
  local nap=$!
  trap 'kill $nap 2>/dev/null; exit 0' TERM
  wait $nap
  kill -ALRM $$
}
watchdog >/dev/null 2>&1 </dev/null &
pids+=($!)

# wait_for SECONDS WHAT COMMAND...: until COMMAND succeeds, or fail naming WHAT.
wait_for() {
  local seconds=$1 what=$2
  shift 2
  for _ in $(seq $((seconds * 5))); do
    if "$@" >/dev/null 2>&1; then return 0; fi
    sleep 0.2
  done
  echo "slurm-check: $what did not come up within $seconds s" >&2
  return 1
}
free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

mkdir -p "$WORK"/{log,munge,db,state,spool,etc}
HOST=$(hostname -s)
USER_NAME=$(id -un)

# munge: a key of our own, its socket in our folder.
chmod 755 "$WORK/munge"  # the socket must be reachable; the key itself is 400
dd if=/dev/urandom of="$WORK/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$WORK/munge/munge.key"
MUNGE_SOCKET=$WORK/munge/munge.socket
munged --foreground --force --key-file="$WORK/munge/munge.key" --socket="$MUNGE_SOCKET" \
  --pid-file="$WORK/munge/munged.pid" --seed-file="$WORK/munge/munge.seed" --log-file="$WORK/log/munged.log" \
  2>"$WORK/log/munged.stderr.log" &
pids+=($!)
wait_for 20 munged test -S "$MUNGE_SOCKET"

# MariaDB on a free loopback port, for slurmdbd.
DB_PORT=$(free_port)
mariadb-install-db --no-defaults --user=root --datadir="$WORK/db" --auth-root-authentication-method=normal \
  --skip-test-db >"$WORK/log/mariadb-install.log" 2>&1
mariadbd --no-defaults --user=root --datadir="$WORK/db" --socket="$WORK/db.sock" --port="$DB_PORT" \
  --bind-address=127.0.0.1 --pid-file="$WORK/db.pid" --log-error="$WORK/log/mariadb.log" >"$WORK/log/mariadb.stderr.log" 2>&1 &
pids+=($!)
wait_for 60 MariaDB mariadb --no-defaults --socket="$WORK/db.sock" -u root -e "select 1"
mariadb --no-defaults --socket="$WORK/db.sock" -u root -e \
  "create user 'slurm'@'127.0.0.1' identified by 'slurm'; grant all on slurm_acct_db.* to 'slurm'@'127.0.0.1';"

DBD_PORT=$(free_port)
CTLD_PORT=$(free_port)
SLURMD_PORT=$(free_port)
export SLURM_CONF=$WORK/etc/slurm.conf
cat >"$WORK/etc/slurmdbd.conf" <<EOF
AuthType=auth/munge
AuthInfo=socket=$MUNGE_SOCKET
DbdHost=localhost
DbdPort=$DBD_PORT
SlurmUser=$USER_NAME
StorageType=accounting_storage/mysql
StorageHost=127.0.0.1
StoragePort=$DB_PORT
StorageUser=slurm
StoragePass=slurm
StorageLoc=slurm_acct_db
LogFile=$WORK/log/slurmdbd.log
PidFile=$WORK/slurmdbd.pid
EOF
chmod 600 "$WORK/etc/slurmdbd.conf"
# One node with this machine's CPUs and 8 GB for jobs; accounting enforced as on a real cluster (a user
# needs an association, i.e. an account, to submit).
cat >"$SLURM_CONF" <<EOF
ClusterName=toolinc-check
SlurmctldHost=$HOST(127.0.0.1)
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
AuthType=auth/munge
AuthInfo=socket=$MUNGE_SOCKET
CredType=cred/munge
SlurmUser=$USER_NAME
SlurmdUser=root
StateSaveLocation=$WORK/state
SlurmdSpoolDir=$WORK/spool
SlurmctldPidFile=$WORK/slurmctld.pid
SlurmdPidFile=$WORK/slurmd.pid
SlurmctldLogFile=$WORK/log/slurmctld.log
SlurmdLogFile=$WORK/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/slurmdbd
AccountingStorageHost=localhost
AccountingStoragePort=$DBD_PORT
AccountingStoragePass=$MUNGE_SOCKET
AccountingStorageEnforce=associations,limits
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=30
NodeName=$HOST NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=8000 State=UNKNOWN
PartitionName=main Nodes=$HOST Default=YES MaxTime=60 State=UP
EOF

slurmdbd -D >"$WORK/log/slurmdbd.stderr.log" 2>&1 &
pids+=($!)
wait_for 60 slurmdbd sacctmgr -n list cluster
sacctmgr -i add cluster toolinc-check >/dev/null
sacctmgr -i add account toolinc-check Description=check Organization=toolinc >/dev/null
sacctmgr -i add user "$USER_NAME" DefaultAccount=toolinc-check >/dev/null
slurmctld -D -i >"$WORK/log/slurmctld.stderr.log" 2>&1 &
pids+=($!)
wait_for 60 slurmctld scontrol ping
slurmd -D -N "$HOST" >"$WORK/log/slurmd.stderr.log" 2>&1 &
pids+=($!)
wait_for 60 "slurmd (node $HOST idle)" bash -c "sinfo -h -N -o %t | grep -qx idle"
echo "slurm-check: one-node Slurm with accounting up ($(sinfo -h -o '%P %D %t'))"

# Sessions: three simulated tools, small (ideal stereo keeps the check short; the pipeline is the same).
SESSIONS=$WORK/sessions
mkdir -p "$SESSIONS"
for spec in hoe:1 hook:2 shovel:3; do
  "$BIN/simulate-session" -q --family "${spec%:*}" --seed "${spec#*:}" --stereo ideal -o "$SESSIONS/${spec%:*}"
done
OUT=$WORK/out
config=(--config sessions="$SESSIONS" out="$OUT" bin="$BIN")
start=$(date +%s)
snakemake -s scripts/Snakefile --cores 2 "${config[@]}" >"$WORK/log/local.log" 2>&1 ||
  { cat "$WORK/log/local.log" >&2; exit 1; }
mv "$OUT" "$WORK/local"
echo "slurm-check: local run done in $(($(date +%s) - start)) s"

# Through the profile, as shipped, with USER unset as in batch shells; stopped by SIGTERM (as a batch
# system's time limit stops it: snakemake lets its running jobs end and submits no more) as soon as its
# first job is done.
start=$(date +%s)
env -u USER snakemake -s scripts/Snakefile --profile scripts/slurm "${config[@]}" >"$WORK/log/slurm-1.log" 2>&1 &
snake=$!
pids+=($snake)
first_done() {
  grep -q "^Finished job" "$WORK/log/slurm-1.log" && return 0
  kill -0 "$snake" 2>/dev/null && return 1
  cat "$WORK/log/slurm-1.log" >&2
  echo "slurm-check: snakemake stopped before a job was done" >&2
  exit 1
}
wait_for 300 "the first job through Slurm" first_done
kill -TERM "$snake"
wait "$snake" || true
echo "slurm-check: first Slurm run killed after $(($(date +%s) - start)) s"
env -u USER snakemake -s scripts/Snakefile --profile scripts/slurm "${config[@]}" >"$WORK/log/slurm-2.log" 2>&1 ||
  { cat "$WORK/log/slurm-2.log" >&2; exit 1; }
echo "slurm-check: second Slurm run done, $(($(date +%s) - start)) s in all"
for run in 1 2; do grep "^toolinc: " "$WORK/log/slurm-$run.log" | sed "s/^/  Slurm run $run: /"; done
grep -q "^toolinc: 3 done, 0 failed, 0 not run, of 3" "$WORK/log/slurm-2.log" ||
  { echo "slurm-check: the second run's table does not say all 3 sessions are done" >&2; exit 1; }
jobs_all=$(grep -cE "^(local)?rule " "$WORK/log/local.log" || true)
jobs_again=$(grep -cE "^(local)?rule " "$WORK/log/slurm-2.log" || true)
echo "slurm-check: the second run ran $jobs_again jobs of the $jobs_all a whole run has"
if [ "$jobs_again" -ge "$jobs_all" ] || [ "$jobs_again" -eq 0 ]; then
  echo "slurm-check: the second run should have done what the first left undone, and only that" >&2
  exit 1
fi
submitted=$(sacct -n -X -a -o JobID | wc -l)
echo "slurm-check: Slurm's accounting lists $submitted jobs"
[ "$submitted" -gt 0 ] || { echo "slurm-check: no job went through Slurm" >&2; exit 1; }

# Every output byte-identical: the same files, the same bytes.
(cd "$WORK/local" && find . -type f ! -path './.snakemake/*' | sort) >"$WORK/local.files"
(cd "$OUT" && find . -type f ! -path './.snakemake/*' | sort) >"$WORK/slurm.files"
if ! diff -u "$WORK/local.files" "$WORK/slurm.files" >&2; then
  echo "slurm-check: the Slurm run's files differ from the local run's" >&2
  exit 1
fi
different=0
while read -r f; do
  cmp -s "$WORK/local/$f" "$OUT/$f" || { echo "slurm-check: $f differs" >&2; different=1; }
done <"$WORK/local.files"
[ $different = 0 ] || exit 1
echo "slurm-check: $(wc -l <"$WORK/local.files") output files, summary.csv among them, byte-identical to the local run's"
