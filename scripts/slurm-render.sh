#!/usr/bin/env bash
# Fans one render out over a cluster as a Slurm job array, then merges the
# parts into the EXR of a single render over all the samples (bit for bit
# the same set sums and estimates; see `gmonrt merge`).
#
#   scripts/slurm-render.sh [options] [scene.pbrt] [-- gmonrt flags...]
#
#   --parts N        array tasks, each a disjoint range of the samples (default 8)
#   --spp N          total samples per pixel (default 1024)
#   --seed N         random seed, the same for every part (default 0)
#   --out DIR        where part-<i>.exr and merged.exr go (default slurm-render)
#   --sbatch "ARGS"  extra sbatch arguments for every job (partition, time, ...)
#   --local          run the parts one after another here, without Slurm
#   --dry-run        print the sbatch commands instead of submitting them
#
# Task i renders samples [i*spp/N, (i+1)*spp/N) with --write-sets; a merge
# job that depends on the whole array (afterok) combines them. Flags after
# `--` go to every part (e.g. --sets 11 --resolution 512x512). gmonrt must be
# built (scripts/build.sh) on a file system the nodes share.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
gmonrt="${GMONRT:-$root/build/gmonrt}"
parts=8 spp=1024 seed=0 out=slurm-render sbatch_args="" mode=submit scene=""
render_flags=()
while [[ $# -gt 0 ]]; do
    case "$1" in
    --parts) parts="$2"; shift 2 ;;
    --spp) spp="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --sbatch) sbatch_args="$2"; shift 2 ;;
    --local) mode=local; shift ;;
    --dry-run) mode=dry-run; shift ;;
    --help | -h) sed -n '2,22p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --) shift; render_flags=("$@"); break ;;
    -*) echo "slurm-render.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) scene="$1"; shift ;;
    esac
done
if ! [[ "$parts" =~ ^[1-9][0-9]*$ && "$spp" =~ ^[1-9][0-9]*$ && "$seed" =~ ^[0-9]+$ ]]; then
    echo "slurm-render.sh: --parts, --spp and --seed take non-negative integers (parts, spp > 0)" >&2
    exit 2
fi
if ((parts > spp)); then
    echo "slurm-render.sh: --parts $parts is more than --spp $spp" >&2
    exit 2
fi
if [[ ! -x "$gmonrt" ]]; then
    echo "slurm-render.sh: $gmonrt not found: run scripts/build.sh first" >&2
    exit 1
fi
mkdir -p "$out"
out="$(cd "$out" && pwd)"
[[ -n "$scene" ]] && scene="$(cd "$(dirname "$scene")" && pwd)/$(basename "$scene")"

# The command of part $1 (its sample range from the part index).
part_command() {
    local i="$1"
    local first=$((i * spp / parts)) next=$(((i + 1) * spp / parts))
    printf '%q ' "$gmonrt" --quiet --write-sets --seed "$seed" --first-sample "$first" --spp "$((next - first))" \
        --outfile "$out/part-$i.exr" "${render_flags[@]}" ${scene:+"$scene"}
}
merge_command() {
    local files=()
    for ((i = 0; i < parts; ++i)); do files+=("$out/part-$i.exr"); done
    printf '%q ' "$gmonrt" merge --outfile "$out/merged.exr" "${files[@]}"
}

case "$mode" in
local)
    for ((i = 0; i < parts; ++i)); do
        echo "part $i/$parts: $(part_command "$i")"
        eval "$(part_command "$i")"
    done
    eval "$(merge_command)"
    ;;
dry-run | submit)
    # One array job: each task computes its own range from SLURM_ARRAY_TASK_ID.
    task_script="$out/part.sh"
    {
        echo '#!/usr/bin/env bash'
        echo 'set -euo pipefail'
        echo "case \"\$SLURM_ARRAY_TASK_ID\" in"
        for ((i = 0; i < parts; ++i)); do echo "$i) exec $(part_command "$i") ;;"; done
        echo 'esac'
    } >"$task_script"
    chmod +x "$task_script"
    array=(sbatch --parsable --job-name=gmon-part --array="0-$((parts - 1))" --output="$out/part-%a.log"
        $sbatch_args "$task_script")
    if [[ "$mode" == dry-run ]]; then
        echo "${array[*]}"
        echo "sbatch --dependency=afterok:<array job id> --job-name=gmon-merge --output=$out/merge.log" \
            "$sbatch_args --wrap \"$(merge_command)\""
        exit 0
    fi
    job=$("${array[@]}")
    job="${job%%;*}"
    merge_job=$(sbatch --parsable --dependency="afterok:$job" --job-name=gmon-merge --output="$out/merge.log" \
        $sbatch_args --wrap "$(merge_command)")
    echo "submitted array job $job ($parts parts) and merge job $merge_job; result: $out/merged.exr"
    ;;
esac
