#!/usr/bin/env bash
# Cost against block count of the three protocols' solvers, one process each, CPU time
# (user + system) by /usr/bin/time: the SBL preset (studies/walls/sbl.toml) generated at
# growing lengths (height, section and joints kept; about 130 blocks per metre),
# realization 0, then
#   tilt   `drystone tilt LAYOUT.json --json`            (penalty DEM, the paper's Kn)
#   limit  `drystone limit LAYOUT.json --json`           (limit analysis)
#   shake  `drystone shake LAYOUT.json --pulse one-sine --amplitude-g 0.1 --period-s 0.2
#           --tail-s 0 --json`                           (nscd, 1 ms steps, 0.2 s pulse
#                                                         after the settling)
# and the ensemble's throughput against thread count (`drystone run` of the main job's
# study with --threads 1 and 2).
#
#   bash scripts/scaling.sh [BIN] [OUT.csv]
#
# BIN defaults to target/release/drystone; the table goes to stdout and OUT.csv.
set -euo pipefail
bin=${1:-target/release/drystone}
out=${2:-scaling.csv}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cpu() { # command... -> CPU seconds (user + system) of the command
    /usr/bin/time -f "%U %S" -o "$work/time" "$@" > "$work/stdout" 2> "$work/stderr" || {
        echo "failed: $*" >&2
        cat "$work/stderr" >&2
        echo nan
        return
    }
    awk '{print $1 + $2}' "$work/time"
}
echo "protocol,length_m,blocks,cpu_s" > "$out"
for length in 0.5 1.5 3.0 6.0 12.0 16.0; do
    sed "s/^length_m = 1.5$/length_m = $length/" studies/walls/sbl.toml > "$work/wall.toml"
    "$bin" generate "$work/wall.toml" --distributions distributions --seed 20210917 --out "$work/w.json" > /dev/null
    blocks=$(python3 -c "import json,sys; print(len(json.load(open(sys.argv[1]))['blocks']))" "$work/w.json")
    for protocol in tilt limit shake; do
        case $protocol in
            tilt) t=$(cpu "$bin" tilt "$work/w.json" --json) ;;
            limit) t=$(cpu "$bin" limit "$work/w.json" --json) ;;
            shake) t=$(cpu "$bin" shake "$work/w.json" --pulse one-sine --amplitude-g 0.1 --period-s 0.2 --tail-s 0 --json) ;;
        esac
        echo "$protocol,$length,$blocks,$t" | tee -a "$out"
    done
done
for threads in 1 2; do
    t0=$(date +%s.%N)
    "$bin" run studies/tilting_table.toml --threads "$threads" --out "$work/run$threads" > /dev/null 2>&1
    t1=$(date +%s.%N)
    echo "ensemble,threads=$threads,36,$(python3 -c "print(f'{$t1 - $t0:.1f}')") s wall" | tee -a "$out"
done
