/* names.c - the names of fields, methods and other option values, one table each, as the CLI parses and prints them. */
#include "names.h"

#include <stdio.h>
#include <string.h>

#define BOTH (CLI_CONVERT | CLI_BENCH)

const cli_name cli_fields[] = {
    {"auto", "auto", JM_FIELD_DEFAULT, CLI_CONVERT}, /* chosen from the first frame */
    {"metasphere", "meta", JM_FIELD_METASPHERE, BOTH},
    {"sph", "sph", JM_FIELD_SPH, BOTH},
    {"sph-aniso", "sphA", (int)CLI_FIELD_SPH_ANISO, CLI_BENCH},
    {NULL, NULL, 0, 0},
};

const cli_name cli_methods[] = {
    {"mt", "mt", JM_METHOD_MT, BOTH},
    {"mc", "mc", JM_METHOD_MC, BOTH},
    {NULL, NULL, 0, 0},
};

const cli_name cli_uv_modes[] = {
    {"box", "box", JM_UV_BOX, CLI_CONVERT},
    {"planar", "planar", JM_UV_PLANAR, CLI_CONVERT},
    {"spherical", "spherical", JM_UV_SPHERICAL, CLI_CONVERT},
    {"none", "none", JM_UV_NONE, CLI_CONVERT},
    {NULL, NULL, 0, 0},
};

const cli_name cli_uv_axes[] = {
    {"x", "x", 1, CLI_CONVERT},
    {"y", "y", 2, CLI_CONVERT},
    {"z", "z", 3, CLI_CONVERT},
    {NULL, NULL, 0, 0},
};

const cli_name *cli_name_find(const cli_name *t, unsigned cmd, const char *s)
{
    for (; t->name; t++)
        if ((t->cmds & cmd) && strcmp(t->name, s) == 0)
            return t;
    return NULL;
}

const char *cli_name_list(const cli_name *t, unsigned cmd, char *buf, size_t len)
{
    size_t n = 0, total = 0, k = 0;
    for (const cli_name *e = t; e->name; e++)
        total += (e->cmds & cmd) != 0;
    buf[0] = '\0';
    for (; t->name; t++) {
        if (!(t->cmds & cmd))
            continue;
        const char *sep = k == 0 ? "" : k + 1 == total ? " or " : ", ";
        int w = snprintf(buf + n, len - n, "%s%s", sep, t->name);
        if (w < 0 || (size_t)w >= len - n)
            break;
        n += (size_t)w;
        k++;
    }
    return buf;
}

const char *cli_name_of(const cli_name *t, int value)
{
    for (; t->name; t++)
        if (t->value == value)
            return t->name;
    return NULL;
}

const char *cli_field_name(jm_field f)
{
    const char *s = f == JM_FIELD_DEFAULT ? NULL : cli_name_of(cli_fields, (int)f);
    return s ? s : cli_name_of(cli_fields, JM_FIELD_METASPHERE);
}

const char *cli_field_column(jm_field f)
{
    for (const cli_name *t = cli_fields; t->name; t++)
        if (f != JM_FIELD_DEFAULT && t->value == (int)f)
            return t->column;
    return f == JM_FIELD_METASPHERE ? "?" : cli_field_column(JM_FIELD_METASPHERE);
}

const char *cli_method_name(jm_method m)
{
    const char *s = m == JM_METHOD_DEFAULT ? NULL : cli_name_of(cli_methods, (int)m);
    return s ? s : cli_name_of(cli_methods, JM_METHOD_MT);
}
