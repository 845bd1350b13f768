# What every bench row starts with, and how it is appended (sourced by the bench scripts).
# A row: date (UTC), commit, machine (cores and CPU model), load (1-minute average), then the bench's figures.
bench_machine() {
  local model
  model=$(awk -F': ' '/^model name/{print $2; exit}' /proc/cpuinfo | tr -s ' ,' ' ')
  echo "$(nproc) cores ${model:-unknown CPU}"
}
BENCH_META="$(date -u +%Y-%m-%dT%H:%M:%S),$(git rev-parse --short HEAD 2>/dev/null || echo unknown),$(bench_machine),$(cut -d' ' -f1 /proc/loadavg)"
# bench_row FILE HEADER FIGURES...: appends "META,FIGURES" to bench/results/FILE (the header first, once)
bench_row() {
  local file=bench/results/$1 header=$2
  shift 2
  mkdir -p bench/results
  [ -s "$file" ] || echo "date,commit,machine,load,$header" > "$file"
  local row=$BENCH_META f
  for f in "$@"; do
    [[ $f == *[,\"]* ]] && f="\"${f//\"/\"\"}\""
    row+=",$f"
  done
  echo "$row" >> "$file"
}
