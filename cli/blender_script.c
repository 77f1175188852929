/* blender_script.c - `jetmesh --blender-script`: finds share/jetmesh/jetmesh_blender.py beside the running binary. */
#include "blender_script.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "convert.h"

#define SCRIPT "share/jetmesh/jetmesh_blender.py"

int blender_script_print(void)
{
    char exe[PATH_MAX], path[PATH_MAX + 64], real[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n > 0) {
        exe[n] = '\0';
        char *slash = strrchr(exe, '/');
        if (slash) {
            *slash = '\0';
            /* PREFIX/bin/jetmesh -> PREFIX/share/...; build/jetmesh -> share/... of the tree */
            snprintf(path, sizeof path, "%s/../" SCRIPT, exe);
            if (access(path, R_OK) == 0 && realpath(path, real)) {
                printf("%s\n", real);
                return EXIT_ALL_OK;
            }
        }
    }
    fprintf(stderr, "jetmesh: cannot find %s beside the jetmesh binary (make install puts it in "
                    "PREFIX/share/jetmesh)\n", SCRIPT);
    return EXIT_RESOURCE;
}
