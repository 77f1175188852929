#!/bin/sh
# t_cli_stats.sh - --stats CSV/JSON: one record per frame with every column, escaping, summary; --stats-svg is valid SVG.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
command -v node >/dev/null 2>&1 || fail "node is needed to validate the JSON"
scratch stats

# five frames: three good ones (one with awkward characters in its name),
# one malformed, one skipped by --resume
mkdir "$T/in" "$T/out"
cp "$S/jet_030.csv" "$T/in/f_30.csv"
cp "$S/jet_031.csv" "$T/in/f_31.csv"
cp "$S/jet_032.csv" "$T/in/f_32.csv"
printf 'x,y,z\n1,2\n' >"$T/in/f_33.csv"
cp "$S/jet_034.csv" "$T/in/f_34.csv"
odd='odd, "name" \ é_35.csv'
cp "$S/jet_035.csv" "$T/in/$odd"
"$J" convert "$T/in/f_34.csv" -r 0.025 -q -o "$T/out/f_34.obj" || fail "setup"

COLS='index,input,output,particles,dropped,vertices,triangles,bytes,ms_read,ms_field,ms_extract,ms_attributes,ms_post,ms_write,ms_total,peak_rss_bytes,lib_peak_bytes,status,error'
for ext in csv json; do
    rm -f "$T"/out/f_3[0-2].obj "$T/out/odd"*
    "$J" convert "$T/in/f_{}.csv" "$T/in/$odd" -r 0.025 -q --keep-going --resume \
        -o "$T/out/" --format obj --stats "$T/stats.$ext" --stats-svg "$T/chart_$ext.svg" 2>"$T/err"
    st=$?
    [ "$st" = 1 ] || { cat "$T/err"; fail "exit $st, not 1 (one frame fails)"; }
    [ -s "$T/stats.$ext" ] || fail "no stats.$ext"
done

node - "$T/stats.json" "$T/stats.csv" "$COLS" <<'EOF' || fail "statistics content (see above)"
const fs = require("fs");
const [jsonPath, csvPath, colList] = process.argv.slice(2);
const cols = colList.split(",");
function check(cond, msg) { if (!cond) { console.error("FAIL: " + msg); process.exit(1); } }

// JSON: parses, one record per frame, every column, summary
const j = JSON.parse(fs.readFileSync(jsonPath, "utf8"));
check(Array.isArray(j.frames) && j.frames.length === 6, "JSON: 6 frame records, got " + (j.frames || []).length);
for (const r of j.frames) for (const c of cols) check(c in r, "JSON: record without " + c);
const by = s => j.frames.filter(r => r.status === s);
check(by("ok").length === 4 && by("failed").length === 1 && by("skipped").length === 1, "JSON: statuses");
const f = by("failed")[0];
check(f.index === 33 && typeof f.error === "string" && f.error.includes("f_33.csv"), "JSON: failed record " + JSON.stringify(f));
check(by("skipped")[0].index === 34, "JSON: the skipped frame is 34");
const odd = j.frames.find(r => r.index === 35);
check(odd && odd.input.endsWith('odd, "name" \\ é_35.csv') && odd.status === "ok", "JSON: escaped name " + (odd && odd.input));
for (const r of by("ok")) {
  check(r.error === null, "JSON: error of an ok frame is null");
  check(r.particles > 0 && r.vertices > 0 && r.triangles > 0 && r.bytes > 0, "JSON: counts of frame " + r.index);
  // the stages add up to the total (each rounded to 0.001 ms)
  const stages = r.ms_read + r.ms_field + r.ms_extract + r.ms_attributes + r.ms_post + r.ms_write;
  check(r.ms_total > 0 && Math.abs(r.ms_total - stages) <= 0.004,
        "JSON: the stages of frame " + r.index + " add up to " + stages + ", not ms_total " + r.ms_total);
  check(r.peak_rss_bytes > 0 && r.lib_peak_bytes > 0, "JSON: memory of frame " + r.index);
  check(fs.statSync(r.output).size === r.bytes, "JSON: bytes = size of " + r.output);
}
const s = j.summary;
for (const k of ["frames", "ok", "failed", "skipped", "ms_total_min", "ms_total_median", "ms_total_p95",
                 "ms_total_max", "wall_seconds", "frames_per_second"]) check(k in s, "JSON: summary without " + k);
check(s.frames === 6 && s.ok === 4 && s.failed === 1 && s.skipped === 1, "JSON: summary counts");
const t = by("ok").map(r => r.ms_total).sort((a, b) => a - b);
check(Math.abs(s.ms_total_min - t[0]) < 0.002 && Math.abs(s.ms_total_max - t[3]) < 0.002, "JSON: min/max");
check(Math.abs(s.ms_total_median - (t[1] + t[2]) / 2) < 0.002, "JSON: median of 4 is the mean of the middle two");
check(Math.abs(s.ms_total_p95 - t[3]) < 0.002, "JSON: p95 nearest rank");
check(s.frames_per_second > 0, "JSON: frames per second");

// CSV: RFC 4180 parse; header; one line per frame; summary comments
const text = fs.readFileSync(csvPath, "utf8");
const lines = [], rows = [];
let row = [], field = "", q = false, i = 0, atStart = true;
while (i < text.length) {
  const ch = text[i];
  if (atStart && ch === "#" && !q) { const e = text.indexOf("\n", i); lines.push(text.slice(i, e)); i = e + 1; continue; }
  atStart = false;
  if (q) {
    if (ch === '"' && text[i + 1] === '"') { field += '"'; i += 2; continue; }
    if (ch === '"') { q = false; i++; continue; }
    field += ch; i++; continue;
  }
  if (ch === '"') { q = true; i++; continue; }
  if (ch === ",") { row.push(field); field = ""; i++; continue; }
  if (ch === "\n") { row.push(field); rows.push(row); row = []; field = ""; i++; atStart = true; continue; }
  field += ch; i++;
}
check(rows.length === 7, "CSV: header + 6 rows, got " + rows.length);
check(rows[0].join(",") === colList, "CSV: header is " + rows[0].join(","));
for (const r of rows) check(r.length === cols.length, "CSV: a row of " + r.length + " fields: " + r.join("|"));
const rec = rows.slice(1).map(r => Object.fromEntries(cols.map((c, k) => [c, r[k]])));
check(rec.filter(r => r.status === "ok").length === 4 && rec.filter(r => r.status === "failed").length === 1 &&
      rec.filter(r => r.status === "skipped").length === 1, "CSV: statuses");
check(rec.some(r => r.input.endsWith('odd, "name" \\ é_35.csv')), "CSV: quoted name");
check(rec.find(r => r.status === "failed").error.includes("f_33.csv"), "CSV: error message");
check(rec.find(r => r.status === "ok").error === "", "CSV: empty error for ok");
const sum = Object.fromEntries(lines.map(l => { const m = /^# summary ([a-z0-9_]+)=(.*)$/.exec(l); check(m, "CSV: summary line " + l); return [m[1], m[2]]; }));
for (const k of ["frames", "ok", "failed", "skipped", "ms_total_min", "ms_total_median", "ms_total_p95",
                 "ms_total_max", "wall_seconds", "frames_per_second"]) check(k in sum, "CSV: summary without " + k);
check(sum.frames === "6" && sum.failed === "1" && sum.skipped === "1", "CSV: summary counts");
check(text.trimEnd().split("\n").slice(-10).every(l => l.startsWith("# summary ")), "CSV: summary lines are at the end");
EOF
echo "ok: CSV and JSON statistics"

# the SVG chart: well-formed standalone SVG with axes, labels and a legend
for svg in "$T/chart_csv.svg" "$T/chart_json.svg"; do
    [ -s "$svg" ] || fail "no $svg"
    if command -v xmllint >/dev/null 2>&1; then
        xmllint --noout "$svg" || fail "$svg is not well-formed XML"
    else
        node -e 'const t=require("fs").readFileSync(process.argv[1],"utf8"); if(!/^<\?xml[^>]*>\s*<svg [^>]*xmlns="http:\/\/www.w3.org\/2000\/svg"/.test(t)||!/<\/svg>\s*$/.test(t)) process.exit(1)' "$svg" ||
            fail "$svg does not look like SVG"
    fi
    head -n 2 "$svg" | grep -q '<svg xmlns="http://www.w3.org/2000/svg"' || fail "$svg: no SVG root"
    for w in read field extract attributes post write 'time (ms)' '>frame<' '>stage<'; do
        grep -q "$w" "$svg" || fail "$svg: no '$w' label"
    done
    [ "$(grep -c '<title>frame ' "$svg")" = 6 ] || fail "$svg: expected 6 bars"
done
grep -q 'odd, &quot;name&quot;' "$T/chart_csv.svg" || fail "SVG does not escape the file name"
echo "ok: SVG chart"

# an empty run of zero converted frames still gives valid reports
printf 'x,y,z\n1,2\n' >"$T/bad.csv"
"$J" convert "$T/bad.csv" -r 0.025 -q -o "$T/bad.obj" --stats "$T/none.json" --stats-svg "$T/none.svg" 2>/dev/null
[ $? = 1 ] || fail "a failed frame must exit 1"
node -e 'const j=JSON.parse(require("fs").readFileSync(process.argv[1],"utf8")); if (j.frames.length!==1||j.summary.ok!==0||j.summary.ms_total_median!==null) process.exit(1)' "$T/none.json" ||
    fail "stats of a run with no converted frame"
if command -v xmllint >/dev/null 2>&1; then xmllint --noout "$T/none.svg" || fail "SVG of a failed run"; fi
if find "$T" -name '*jetmesh-tmp*' | grep -q .; then fail "temporaries left"; fi
# post-processing has its column, and with it (and interpolated
# --attributes, counted with attributes) the stages add up to the total
# (issue 32: with --smooth they did not)
"$J" convert "$ROOT/samples/real/double_dam_break_frame_26_4732_particles.vtk" -r 0.025 --field sph -q \
    --smooth 5 --simplify 0.1 --attributes velocity -o "$T/post.ply" --stats "$T/post.csv" || fail "--smooth run"
"$J" stats merge "$T/post.csv" -o "$T/post_m.json" -q || fail "stats merge to JSON"
node - "$T/post_m.json" "$T/post.csv" <<'EOF' || fail "post-processing column (see above)"
const fs = require("fs");
const j = JSON.parse(fs.readFileSync(process.argv[2], "utf8"));
const r = j.frames[0];
const sum = r.ms_read + r.ms_field + r.ms_extract + r.ms_attributes + r.ms_post + r.ms_write;
if (!(r.ms_post > 0)) { console.error("FAIL: ms_post " + r.ms_post + " with --smooth"); process.exit(1); }
if (Math.abs(sum - r.ms_total) > 0.004) { console.error(`FAIL: stages ${sum} against total ${r.ms_total}`); process.exit(1); }
const csv = fs.readFileSync(process.argv[3], "utf8").split("\n");
const head = csv[0].split(","), row = csv[1].split(",");
if (Number(row[head.indexOf("ms_post")]) !== r.ms_post) { console.error("FAIL: CSV and merged JSON ms_post differ"); process.exit(1); }
EOF
# reports written before the column (no ms_post) still merge, with 0 there
old='index,input,output,particles,dropped,vertices,triangles,bytes,ms_read,ms_field,ms_extract,ms_attributes,ms_write,ms_total,peak_rss_bytes,lib_peak_bytes,status,error'
printf '%s\n0,a.csv,a.obj,10,0,20,36,900,1.000,2.000,3.000,4.000,5.000,15.000,100,50,ok,\n# summary wall_seconds=0.100\n' \
    "$old" >"$T/old_0.csv"
printf '{"frames": [{"index": 1, "input": "b.csv", "output": "b.obj", "particles": 10, "dropped": 0, "vertices": 20, "triangles": 36, "bytes": 900, "ms_read": 1.0, "ms_field": 2.0, "ms_extract": 3.0, "ms_attributes": 4.0, "ms_write": 5.0, "ms_total": 15.0, "peak_rss_bytes": 100, "lib_peak_bytes": 50, "status": "ok", "error": null}], "summary": {"wall_seconds": 0.1}}\n' \
    >"$T/old_1.json"
"$J" stats merge "$T/old_0.csv" "$T/old_1.json" -o "$T/old_m.json" -q || fail "stats merge of reports without ms_post"
node -e 'const j=JSON.parse(require("fs").readFileSync(process.argv[1],"utf8"));
  if (j.frames.length!==2||j.frames.some(r=>r.ms_post!==0||r.ms_write!==5||r.ms_total!==15)) process.exit(1)' "$T/old_m.json" ||
    fail "old reports merged wrongly: $(cat "$T/old_m.json")"
echo "ok: post-processing column, stages add up, old reports merge"
echo "all statistics checks passed"
