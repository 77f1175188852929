#!/bin/sh
# t_pkgconfig.sh - make install into a scratch PREFIX installs jetmesh.pc, the Blender script and the man page; a C program builds with pkg-config against it and runs.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch pkgconfig
command -v pkg-config >/dev/null 2>&1 || fail "pkg-config is missing: apt-get install pkg-config"
B=${JETMESH_BUILD:-$ROOT/build}
P=$T/prefix
make -C "$ROOT" --no-print-directory install PREFIX="$P" BUILD="$B" >"$T/install.log" 2>&1 ||
    { tail -n 20 "$T/install.log"; fail "make install PREFIX=$P"; }
for f in bin/jetmesh lib/libjetmesh.so lib/libjetmesh.a include/jetmesh.h lib/pkgconfig/jetmesh.pc \
         share/jetmesh/jetmesh_blender.py share/man/man1/jetmesh.1; do
    [ -f "$P/$f" ] || fail "make install did not install $f"
done
export PKG_CONFIG_PATH="$P/lib/pkgconfig"
want=$(sed -n 's/^#define JM_VERSION_STRING "\(.*\)"/\1/p' "$ROOT/lib/jetmesh.h")
[ "$(pkg-config --modversion jetmesh)" = "$want" ] || fail "pkg-config --modversion: $(pkg-config --modversion jetmesh)"
cat >"$T/use.c" <<'C'
#include <jetmesh.h>
#include <stdio.h>
#include <stdlib.h>
int main(void)
{
    const float xyz[6] = {0, 0, 0, 0.03f, 0, 0};
    const float vel[6] = {1, 0, 0, 1, 0, 0};
    jm_params p = {0};
    p.radius = 0.025f;
    jm_context *ctx;
    if (jm_context_create(&p, &ctx) != JM_OK) return 1;
    jm_particles in = {xyz, 2, 0, NULL};
    jm_mesh m;
    if (jm_mesh_particles(ctx, &in, &m, NULL) != JM_OK) return 1;
    float *out = malloc(m.vertex_count * 3 * sizeof *out);
    jm_attribute a = {3, vel, out};
    if (jm_interpolate_attributes(&p, &in, m.positions, m.vertex_count, &a, 1) != JM_OK) return 1;
    printf("jetmesh %s: %zu vertices, %zu triangles, velocity %g\n", jm_version(), m.vertex_count,
           m.triangle_count, (double)out[0]);
    free(out);
    jm_context_free(ctx);
    return 0;
}
C
# shellcheck disable=SC2046
cc -o "$T/use" "$T/use.c" $(pkg-config --cflags --libs jetmesh) || fail "cc with pkg-config --cflags --libs jetmesh"
LD_LIBRARY_PATH="$P/lib" "$T/use" >"$T/use.out" || fail "the program built against the installed tree failed"
grep -q "^jetmesh $want: [1-9][0-9]* vertices, [1-9][0-9]* triangles, velocity 1$" "$T/use.out" ||
    fail "unexpected output: $(cat "$T/use.out")"
# shellcheck disable=SC2046
cc -o "$T/use_static" "$T/use.c" "$P/lib/libjetmesh.a" $(pkg-config --cflags --libs-only-other --static jetmesh) \
    $(pkg-config --libs-only-l --static jetmesh | sed 's/-ljetmesh//') || fail "static link with pkg-config --static"
"$T/use_static" >/dev/null || fail "the static program failed"
[ "$("$P/bin/jetmesh" --blender-script)" = "$P/share/jetmesh/jetmesh_blender.py" ] ||
    fail "the installed jetmesh --blender-script printed $("$P/bin/jetmesh" --blender-script)"
echo "ok: jetmesh.pc $want; a program built with pkg-config runs against the installed tree; --blender-script finds the installed script"
