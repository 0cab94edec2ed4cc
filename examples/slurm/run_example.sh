#!/usr/bin/env bash
# Runs a small study as a Slurm job array on the local cluster (setup_single_node.sh), merges
# the shards, checks that `merge` names a lost shard and that a killed task submitted again
# resumes from its journal, and compares the merged outputs with an unsharded run of the same
# study: every file byte for byte, realizations.csv with its wall_time_s column blanked
# (realizations.parquet holds the same rows and the wall times).
#
#   examples/slurm/run_example.sh        # from the repository root, after cargo build --release
#
# Environment: DRYSTONE [target/release/drystone], STUDY [studies/tilting_table.toml],
# RUN_ARGS [--realizations 2], TASKS [3], WORK [a new temporary directory].
# Exit status 0 when everything matches.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
DRYSTONE=$(realpath "${DRYSTONE:-target/release/drystone}")
STUDY=$(realpath "${STUDY:-studies/tilting_table.toml}")
RUN_ARGS=${RUN_ARGS:---realizations 2}
TASKS=${TASKS:-3}
WORK=${WORK:-$(mktemp -d /tmp/drystone-slurm.XXXXXX)}
mkdir -p "$WORK/logs"
env=(--export=ALL,STUDY="$STUDY",OUT="$WORK",DRYSTONE="$DRYSTONE",RUN_ARGS="$RUN_ARGS",SHARDS="$TASKS")

# Waits for jobs to leave the queue (at most 20 minutes) and fails if one did not complete.
wait_jobs() {
    for _ in $(seq 1 1200); do
        [ -z "$(squeue -h -j "$1" 2>/dev/null)" ] && break
        sleep 1
    done
    local bad
    bad=$(scontrol -o show job "$1" 2>/dev/null | grep -v 'JobState=COMPLETED' || true)
    if [ -n "$bad" ]; then
        echo "run_example.sh: job $1 did not complete:" >&2
        echo "$bad" | grep -o 'JobId=[0-9]* \|ArrayTaskId=[0-9]*\|JobState=[A-Z_]*' >&2
        return 1
    fi
}

echo "== array of $TASKS tasks: $DRYSTONE run $STUDY $RUN_ARGS --shard K/$TASKS --resume"
array=$(sbatch --parsable --chdir="$root" --array=0-$((TASKS - 1)) "${env[@]}" \
    --output="$WORK/logs/shard-%a.log" examples/slurm/array.sbatch)
merge=$(sbatch --parsable --chdir="$root" --dependency=afterok:"$array" "${env[@]}" \
    --output="$WORK/logs/merge.log" examples/slurm/merge.sbatch)
wait_jobs "$array"
wait_jobs "$merge"
cat "$WORK/logs/merge.log"

echo "== a lost shard: merge names it"
rm -rf "$WORK/merged"
if "$DRYSTONE" merge --out "$WORK/merged" $(ls -d "$WORK"/shard-*/ | grep -v "/shard-2/$") 2>"$WORK/logs/missing.err"; then
    echo "run_example.sh: merge accepted a missing shard" >&2
    exit 1
fi
cat "$WORK/logs/missing.err"
grep -q "shard 2/$TASKS missing" "$WORK/logs/missing.err"

echo "== a killed task (shard 2 left with the first row of its journal): submitted again, it resumes"
head -n 2 "$WORK/shard-2/journal.jsonl" >"$WORK/journal.part"
rm -rf "$WORK/shard-2" && mkdir "$WORK/shard-2" && mv "$WORK/journal.part" "$WORK/shard-2/journal.jsonl"
again=$(sbatch --parsable --chdir="$root" --array=1 "${env[@]}" \
    --output="$WORK/logs/shard-%a.again.log" examples/slurm/array.sbatch)
wait_jobs "$again"
cat "$WORK/logs/shard-1.again.log"
grep -q "1 from the journal" "$WORK/logs/shard-1.again.log"
merge=$(sbatch --parsable --chdir="$root" "${env[@]}" --output="$WORK/logs/merge.again.log" examples/slurm/merge.sbatch)
wait_jobs "$merge"
cat "$WORK/logs/merge.again.log"

echo "== unsharded run and comparison"
# shellcheck disable=SC2086
"$DRYSTONE" run "$STUDY" --out "$WORK/whole" --threads 1 $RUN_ARGS >"$WORK/logs/whole.log"
blank_wall_time() {
    awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "wall_time_s") c = i } { if (c) $c = ""; print }' OFS=, "$1"
}
status=0
compared=0
for f in $(cd "$WORK/whole" && find . -type f ! -name journal.jsonl ! -name 'realizations.*' ! -name .drystone.lock ! -name manifest.json | sort); do
    compared=$((compared + 1))
    if ! cmp -s "$WORK/whole/$f" "$WORK/merged/$f"; then
        echo "differs: $f"
        status=1
    fi
done
if ! diff <(blank_wall_time "$WORK/whole/realizations.csv") <(blank_wall_time "$WORK/merged/realizations.csv") >/dev/null; then
    echo "differs: realizations.csv (beyond wall_time_s)"
    status=1
fi
extra=$(cd "$WORK/merged" && find . -type f ! -name journal.jsonl ! -name .drystone.lock | sort | while read -r f; do [ -e "$WORK/whole/$f" ] || echo "$f"; done)
[ -z "$extra" ] || { echo "only in the merged outputs: $extra"; status=1; }
if [ $status = 0 ]; then
    echo "identical: $compared files byte for byte and realizations.csv but for wall_time_s ($WORK)"
fi
exit $status
