#!/usr/bin/env bash
# `mpirun -np 2 rockwatch study --mpi` against the single-process study on small plans: the files byte for byte
# (one wall: runs.csv, summary.json, table3.md; a portfolio: runs.csv, summary.json, walls_summary.csv), a study
# whose ranks get SIGTERM (as scancel sends it to every task) saving a resumable state that --resume under mpirun
# finishes to the same files, and an input error reported once, exit 2.
#   study_mpi.sh SOURCE_DIR ROCKWATCH_BINARY MPIEXEC
# In a container: OMPI_MCA_btl_vader_single_copy_mechanism=none (no CMA between the ranks), OMPI_MCA_plm_rsh_agent=
# (no ssh needed to start local ranks); --allow-run-as-root when root; --oversubscribe for 2 ranks on any machine.
set -euo pipefail
src=$(readlink -f "$1")
rockwatch=$(readlink -f "$2")
mpiexec=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
export OMPI_MCA_btl_vader_single_copy_mechanism=${OMPI_MCA_btl_vader_single_copy_mechanism-none}
export OMPI_MCA_plm_rsh_agent=${OMPI_MCA_plm_rsh_agent-}
mpirun=("$mpiexec" -np 2 --oversubscribe)
if [ "$(id -u)" -eq 0 ]; then mpirun+=(--allow-run-as-root); fi
suite=$src/sim/suites/npr9998-2015

same() {  # same DIR_A DIR_B FILE...
  local a=$1 b=$2
  shift 2
  for f in "$@"; do
    cmp "$a/$f" "$b/$f" || { echo "FAIL: $b/$f differs from $a/$f"; exit 1; }
  done
}

# One wall: 2 records x 5 levels x 2 r x 2 vertical.
plan=(--suite "$suite" --sets 1 --pga 0.15:0.23:0.02)
"$rockwatch" study "${plan[@]}" --out single >/dev/null 2>&1
"${mpirun[@]}" "$rockwatch" study --mpi "${plan[@]}" --out mpi >mpi.out 2>mpi.err || { cat mpi.err; exit 1; }
grep -q "on 2 MPI ranks" mpi.err || { echo "FAIL: not 2 ranks:"; cat mpi.err; exit 1; }
same single mpi runs.csv summary.json table3.md
echo "one wall: mpirun -np 2 = single process"

# A portfolio of 3 walls.
printf 'id,b,h1,h2,rho,fp,a,a_prime\npaper,,,,,,,\nthick,0.14,1.5,1.6,,,,\nloaded,,,,,3000,0.5,0.5\n' >walls.csv
plan=(--suite "$suite" --sets 1 --pga 0.15:0.23:0.02 --r exp --walls walls.csv)
"$rockwatch" study "${plan[@]}" --out psingle >/dev/null 2>&1
"${mpirun[@]}" "$rockwatch" study --mpi "${plan[@]}" --out pmpi >/dev/null 2>pmpi.err || { cat pmpi.err; exit 1; }
same psingle pmpi runs.csv summary.json walls_summary.csv
echo "portfolio: mpirun -np 2 = single process"

# SIGTERM to the ranks mid-study, then --resume (fine steps: a few seconds).
plan=(--suite "$suite" --sets 1-6 --r exp --vertical without --max-step 0.0001)
"${mpirun[@]}" "$rockwatch" study --mpi "${plan[@]}" --out killed >killed.out 2>killed.err &
pid=$!
for _ in $(seq 1 3000); do
  grep -q "analyses (" killed.err 2>/dev/null && break
  sleep 0.01
done
ranks=$(ps -o pid= --ppid "$pid" || true)
for rank in $ranks; do kill -TERM "$rank" 2>/dev/null || true; done
status=0
wait "$pid" || status=$?
if grep -q '"state": "interrupted"' killed/study.json; then
  [ "$status" -ne 0 ] || { echo "FAIL: interrupted but exit status 0"; exit 1; }
  grep -q "interrupted by SIGTERM" killed.err || { echo "FAIL: no interruption message:"; cat killed.err; exit 1; }
  "${mpirun[@]}" "$rockwatch" study --mpi "${plan[@]}" --out killed --resume >/dev/null 2>resumed.err ||
    { cat resumed.err; exit 1; }
  grep -q "resuming: " resumed.err || { echo "FAIL: not resumed:"; cat resumed.err; exit 1; }
  echo "SIGTERM: $(grep -o 'resuming: [0-9]* of [0-9]*' resumed.err), resumed under mpirun"
else
  echo "note: the study ended before SIGTERM reached it: interrupt check skipped"
fi
"$rockwatch" study "${plan[@]}" --out whole >/dev/null 2>&1
same whole killed runs.csv summary.json table3.md
echo "interrupted + resumed = single process"

# An input error: exit 2, said once (by rank 0).
status=0
"${mpirun[@]}" "$rockwatch" study --mpi --suite "$suite" --walls missing.csv --out bad >bad.out 2>bad.err || status=$?
[ "$status" -eq 2 ] || { echo "FAIL: exit $status for a missing --walls file"; cat bad.err; exit 1; }
[ "$(grep -c 'missing.csv' bad.err)" -ge 1 ] || { echo "FAIL: no message"; cat bad.err; exit 1; }
printf 'id,b,h1,h2,rho,fp,a,a_prime\nw,0.1x,,,,,,\n' >bad.csv
status=0
"${mpirun[@]}" "$rockwatch" study --mpi --suite "$suite" --walls bad.csv --out bad >bad.out 2>bad.err || status=$?
[ "$status" -eq 2 ] || { echo "FAIL: exit $status for a bad row"; cat bad.err; exit 1; }
[ "$(grep -c 'bad.csv:2:' bad.err)" -eq 1 ] || { echo "FAIL: the bad row not named exactly once:"; cat bad.err; exit 1; }
echo "input errors: exit 2, named once"
