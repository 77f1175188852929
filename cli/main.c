/* main.c - the jetmesh command: dispatches to convert, generate, bench and help. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/jetmesh.h"
#include "../lib/jetmesh_testing.h"
#include "bench/bench.h"
#include "blender_script.h"
#include "convert.h"
#include "generate.h"
#include "options.h"
#include "stats/stats_merge.h"
#include "stdout_check.h"

static void usage(FILE *f)
{
    fputs("Usage: jetmesh COMMAND [options]\n"
          "Turns particle simulation frames into triangle meshes with normals and UVs.\n"
          "\n"
          "Commands:\n"
          "  convert [options] INPUT... -o OUTPUT   mesh particle frames\n"
          "  generate SCENE [N] -o OUTPUT           write a synthetic scene (jet, block N, spray N)\n"
          "  bench [options] [SCENE [N] | INPUT...] time the library\n"
          "  stats merge STATS... -o OUT            one report from the --stats of shards\n"
          "  help [COMMAND]                         help on a command\n"
          "\n"
          "  jetmesh --help      this help\n"
          "  jetmesh --version   the version\n"
          "  jetmesh --blender-script   the path of the Blender streaming importer:\n"
          "                      blender --python \"$(jetmesh --blender-script)\" -- meshes/\n"
          "\n"
          "Example: jetmesh convert 'frames/jet_{}.csv' -r 0.025 -o 'meshes/jet_{}.glb'\n"
          "See jetmesh(1) and 'jetmesh COMMAND --help'.\n",
          f);
}

static int help(const char *cmd)
{
    if (!cmd) {
        usage(stdout);
        return 0;
    }
    if (strcmp(cmd, "convert") == 0)
        options_convert_help(stdout);
    else if (strcmp(cmd, "generate") == 0)
        options_generate_help(stdout);
    else if (strcmp(cmd, "stats") == 0)
        stats_merge_help(stdout);
    else if (strcmp(cmd, "bench") == 0) {
        char name[] = "bench", opt[] = "--help";
        char *args[] = {name, opt, NULL};
        return cmd_bench(2, args);
    } else {
        fprintf(stderr, "jetmesh: no command '%s'\nTry 'jetmesh --help' for more information.\n", cmd);
        return 2;
    }
    return 0;
}

static int run_command(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "jetmesh: no command: give convert, generate, bench or help\n"
                        "Try 'jetmesh --help' for more information.\n");
        return 2;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "version") == 0) {
        printf("jetmesh %s\n", JM_VERSION_STRING);
        return 0;
    }
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0)
        return help(NULL);
    if (strcmp(cmd, "--blender-script") == 0)
        return blender_script_print();
    if (strcmp(cmd, "help") == 0)
        return help(argc > 2 ? argv[2] : NULL);
    if (strcmp(cmd, "convert") == 0)
        return cmd_convert(argc - 1, argv + 1);
    if (strcmp(cmd, "generate") == 0)
        return cmd_generate(argc - 1, argv + 1);
    if (strcmp(cmd, "bench") == 0)
        return cmd_bench(argc - 1, argv + 1);
    if (strcmp(cmd, "stats") == 0)
        return cmd_stats(argc - 1, argv + 1);
    fprintf(stderr, "jetmesh: unknown command '%s'\nTry 'jetmesh --help' for more information.\n", cmd);
    return 2;
}

int main(int argc, char **argv)
{
    /* tests only (tests/t_splat_variants.sh): the library's vector level,
     * 0 plain C to 3 AVX-512 (jetmesh_testing.h) */
    const char *cpu = getenv("JETMESH_TESTING_CPU");
    if (cpu && *cpu) jm_testing_force_cpu(atoi(cpu));
    return stdout_finish(run_command(argc, argv));
}
