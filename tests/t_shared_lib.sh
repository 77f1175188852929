#!/bin/sh
# t_shared_lib.sh - the public header alone is enough: a C program linked to libjetmesh.so and a C++ include both work.
set -e
root=${JETMESH_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
build=${JETMESH_BUILD:-$root/build}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
mkdir "$tmp/include"
cp "$root/lib/jetmesh.h" "$tmp/include/"     # only the installed header
cat > "$tmp/app.c" <<'C'
#include <jetmesh.h>
#include <stdio.h>
#include <string.h>
int main(void)
{
    jm_params p;
    memset(&p, 0, sizeof p);
    p.radius = 0.5f;
    jm_context *ctx = NULL;
    if (jm_context_create(&p, &ctx) != JM_OK) return 1;
    float xyz[3] = {0.1f, 0.2f, 0.3f};
    jm_particles in = {xyz, 1, 0, NULL};
    jm_mesh m;
    jm_stats st;
    jm_status s = jm_mesh_particles(ctx, &in, &m, &st);
    printf("%s %s %zu %zu\n", jm_version(), jm_status_message(s), m.vertex_count, m.triangle_count);
    int ok = s == JM_OK && m.triangle_count > 100 && m.normals && m.uvs;
    jm_context_free(ctx);
    jm_context_free(NULL);
    return ok ? 0 : 1;
}
C
cc -std=c11 -Wall -Wextra -Werror -I"$tmp/include" "$tmp/app.c" -L"$build" -ljetmesh -Wl,-rpath,"$build" -o "$tmp/app"
# the program must really use the shared library
ldd "$tmp/app" | grep -q "libjetmesh.so" || { echo "not linked to libjetmesh.so"; exit 1; }
"$tmp/app"
printf '#include <jetmesh.h>\nint main() { jm_params p{}; p.radius = 1; jm_context *c = nullptr; return jm_context_create(&p, &c) == JM_OK ? (jm_context_free(c), 0) : 1; }\n' > "$tmp/app.cpp"
c++ -std=c++11 -Wall -Wextra -Werror -I"$tmp/include" "$tmp/app.cpp" -L"$build" -ljetmesh -Wl,-rpath,"$build" -o "$tmp/appxx"
"$tmp/appxx"
echo "shared library and header: ok"
