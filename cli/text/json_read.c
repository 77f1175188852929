/* json_read.c - reads JSON as it goes: objects member by member, arrays element by element, strings decoded, scalars as text. */
#include "json_read.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void json_ws(text_cursor *r)
{
    while (r->p < r->end && (*r->p == ' ' || *r->p == '\t' || *r->p == '\n' || *r->p == '\r'))
        r->p++;
}

int json_expect(text_cursor *r, char c)
{
    json_ws(r);
    if (r->p >= r->end || *r->p != c) {
        char msg[64];
        snprintf(msg, sizeof msg, "expected '%c' in the JSON", c);
        return text_fail(r, msg);
    }
    r->p++;
    return 0;
}

static void put_utf8(char *b, size_t *n, unsigned v)
{
    if (v < 0x80) {
        b[(*n)++] = (char)v;
    } else if (v < 0x800) {
        b[(*n)++] = (char)(0xc0 | (v >> 6));
        b[(*n)++] = (char)(0x80 | (v & 0x3f));
    } else if (v < 0x10000) {
        b[(*n)++] = (char)(0xe0 | (v >> 12));
        b[(*n)++] = (char)(0x80 | ((v >> 6) & 0x3f));
        b[(*n)++] = (char)(0x80 | (v & 0x3f));
    } else {
        b[(*n)++] = (char)(0xf0 | (v >> 18));
        b[(*n)++] = (char)(0x80 | ((v >> 12) & 0x3f));
        b[(*n)++] = (char)(0x80 | ((v >> 6) & 0x3f));
        b[(*n)++] = (char)(0x80 | (v & 0x3f));
    }
}

static int hex4(text_cursor *r, unsigned *v)
{
    *v = 0;
    for (int i = 0; i < 4; i++) {
        if (r->p >= r->end)
            return -1;
        char c = *r->p++;
        unsigned d = c >= '0' && c <= '9' ? (unsigned)(c - '0')
                     : c >= 'a' && c <= 'f' ? (unsigned)(c - 'a' + 10)
                     : c >= 'A' && c <= 'F' ? (unsigned)(c - 'A' + 10) : 16u;
        if (d > 15)
            return -1;
        *v = *v * 16 + d;
    }
    return 0;
}

int json_string(text_cursor *r, char **out)
{
    if (json_expect(r, '"') != 0)
        return -1;
    size_t cap = 64, n = 0;
    char *b = malloc(cap + 8);
    if (!b)
        return text_fail(r, "out of memory");
    for (;;) {
        if (r->p >= r->end) {
            free(b);
            return text_fail(r, "a JSON string does not end");
        }
        if (n + 8 > cap) {
            char *nb = realloc(b, (cap *= 2) + 8);
            if (!nb) {
                free(b);
                return text_fail(r, "out of memory");
            }
            b = nb;
        }
        char c = *r->p++;
        if (c == '"')
            break;
        if (c != '\\') {
            b[n++] = c;
            continue;
        }
        if (r->p >= r->end)
            continue;
        c = *r->p++;
        unsigned v;
        switch (c) {
        case 'n': b[n++] = '\n'; break;
        case 'r': b[n++] = '\r'; break;
        case 't': b[n++] = '\t'; break;
        case 'b': b[n++] = '\b'; break;
        case 'f': b[n++] = '\f'; break;
        case 'u':
            if (hex4(r, &v) != 0) {
                free(b);
                return text_fail(r, "a bad \\u escape in a JSON string");
            }
            if (v >= 0xd800 && v <= 0xdbff && r->end - r->p >= 6 && r->p[0] == '\\' && r->p[1] == 'u') {
                unsigned lo;
                r->p += 2;
                if (hex4(r, &lo) == 0 && lo >= 0xdc00 && lo <= 0xdfff)
                    v = 0x10000 + ((v - 0xd800) << 10) + (lo - 0xdc00);
                else
                    v = 0xfffd;
            } else if (v >= 0xd800 && v <= 0xdfff)
                v = 0xfffd;
            put_utf8(b, &n, v);
            break;
        default: b[n++] = c; break; /* \" \\ \/ */
        }
    }
    b[n] = '\0';
    *out = b;
    return 0;
}

int json_scalar(text_cursor *r, char **out, int *is_container)
{
    json_ws(r);
    *out = NULL;
    *is_container = 0;
    if (r->p >= r->end)
        return text_fail(r, "the JSON ends early");
    if (*r->p == '"')
        return json_string(r, out);
    if (*r->p == '{' || *r->p == '[') {
        *is_container = 1;
        return 0;
    }
    const char *s = r->p;
    while (r->p < r->end && !strchr(",}] \t\r\n", *r->p))
        r->p++;
    size_t len = (size_t)(r->p - s);
    if (len == 0)
        return text_fail(r, "a JSON value expected");
    if (len == 4 && strncmp(s, "null", 4) == 0)
        return 0;
    *out = malloc(len + 1);
    if (!*out)
        return text_fail(r, "out of memory");
    memcpy(*out, s, len);
    (*out)[len] = '\0';
    return 0;
}

static int skip(text_cursor *r, int depth);

/* Skips the object or array at r->p. */
static int skip_container(text_cursor *r, int depth)
{
    if (depth > 64)
        return text_fail(r, "JSON nested too deeply");
    json_ws(r);
    char close = *r->p == '{' ? '}' : ']';
    int object = close == '}';
    r->p++;
    json_ws(r);
    if (r->p < r->end && *r->p == close) {
        r->p++;
        return 0;
    }
    for (;;) {
        if (object) {
            char *k;
            if (json_string(r, &k) != 0)
                return -1;
            free(k);
            if (json_expect(r, ':') != 0)
                return -1;
        }
        if (skip(r, depth + 1) != 0)
            return -1;
        json_ws(r);
        if (r->p < r->end && *r->p == ',') {
            r->p++;
            continue;
        }
        return json_expect(r, close);
    }
}

static int skip(text_cursor *r, int depth)
{
    char *t;
    int cont;
    if (json_scalar(r, &t, &cont) != 0)
        return -1;
    free(t);
    return cont ? skip_container(r, depth) : 0;
}

int json_members(text_cursor *r, int (*each)(text_cursor *, const char *, void *), void *user)
{
    if (json_expect(r, '{') != 0)
        return -1;
    json_ws(r);
    if (r->p < r->end && *r->p == '}') {
        r->p++;
        return 0;
    }
    for (;;) {
        char *k;
        if (json_string(r, &k) != 0)
            return -1;
        int rc = json_expect(r, ':') == 0 ? each(r, k, user) : -1;
        free(k);
        if (rc != 0)
            return -1;
        json_ws(r);
        if (r->p < r->end && *r->p == ',') {
            r->p++;
            continue;
        }
        return json_expect(r, '}');
    }
}

int json_skip(text_cursor *r)
{
    return skip(r, 1);
}

int json_skip_container(text_cursor *r)
{
    return skip_container(r, 1);
}

int json_elements(text_cursor *r, int (*each)(text_cursor *, void *), void *user)
{
    if (json_expect(r, '[') != 0)
        return -1;
    json_ws(r);
    if (r->p < r->end && *r->p == ']') {
        r->p++;
        return 0;
    }
    for (;;) {
        if (each(r, user) != 0)
            return -1;
        json_ws(r);
        if (r->p < r->end && *r->p == ',') {
            r->p++;
            continue;
        }
        return json_expect(r, ']');
    }
}
