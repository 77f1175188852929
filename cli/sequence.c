/* sequence.c - expands input patterns into ordered frames and names each frame's output file. */
#include "sequence.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static void seq_err(char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || errlen == 0)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

static char *seq_strdup(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d)
        memcpy(d, s, n);
    return d;
}

/* Parses a whole non-negative decimal number; 0 on success. */
static int parse_index(const char *s, size_t len, long *out)
{
    if (len == 0 || len > 18)
        return -1;
    long v = 0;
    for (size_t i = 0; i < len; i++) {
        if (!isdigit((unsigned char)s[i]))
            return -1;
        v = v * 10 + (s[i] - '0');
    }
    *out = v;
    return 0;
}

static int parse_long_field(const char *s, size_t len, long *out)
{
    if (len == 0)
        return -1;
    int neg = 0;
    if (s[0] == '-' || s[0] == '+') {
        neg = s[0] == '-';
        s++;
        len--;
    }
    if (parse_index(s, len, out) != 0)
        return -1;
    if (neg)
        *out = -*out;
    return 0;
}

int seq_range_parse(const char *text, seq_range *out, char *err, size_t errlen)
{
    long v[3] = {0, 0, 1};
    int nf = 0;
    const char *p = text ? text : "";
    for (;;) {
        const char *colon = strchr(p, ':');
        size_t len = colon ? (size_t)(colon - p) : strlen(p);
        if (nf == 3) {
            seq_err(err, errlen, "bad frame range '%s': expected START:END[:STEP]", text);
            return -1;
        }
        if (parse_long_field(p, len, &v[nf]) != 0) {
            seq_err(err, errlen, "bad frame range '%s': expected START:END[:STEP] with whole numbers from 0 to "
                    "999999999999999999", text);
            return -1;
        }
        nf++;
        if (!colon)
            break;
        p = colon + 1;
    }
    if (nf == 1)
        v[1] = v[0];
    if (v[0] < 0 || v[1] < 0) {
        seq_err(err, errlen, "bad frame range '%s': frame numbers are never negative", text);
        return -1;
    }
    if (v[1] < v[0]) {
        seq_err(err, errlen, "bad frame range '%s': END is before START (END is inclusive)", text);
        return -1;
    }
    if (v[2] < 1) {
        seq_err(err, errlen, "bad frame range '%s': STEP must be 1 or more", text);
        return -1;
    }
    out->start = v[0];
    out->end = v[1];
    out->step = v[2];
    out->set = 1;
    return 0;
}

int seq_range_contains(const seq_range *r, long index)
{
    if (!r || !r->set)
        return 1;
    return index >= r->start && index <= r->end && (index - r->start) % r->step == 0;
}

/* Finds the placeholder of s: kind, offset and length. Returns the kind. */
static seq_kind find_placeholder(const char *s, size_t *at, size_t *len, int *width, int *zero)
{
    int braces = 0, printfs = 0;
    for (size_t i = 0; s[i]; i++) {
        if (s[i] == '{' && s[i + 1] == '}') {
            if (braces + printfs == 0) {
                *at = i;
                *len = 2;
            }
            braces++;
            i++;
        } else if (s[i] == '%') {
            if (s[i + 1] == '%') {
                i++;
                continue;
            }
            size_t j = i + 1;
            int z = 0, w = 0;
            if (s[j] == '0') {
                z = 1;
                j++;
            }
            while (isdigit((unsigned char)s[j]) && w < 100)
                w = w * 10 + (s[j++] - '0');
            if (s[j] == 'd') {
                if (braces + printfs == 0) {
                    *at = i;
                    *len = j + 1 - i;
                    *width = w;
                    *zero = z;
                }
                printfs++;
                i = j;
            }
        }
    }
    if (braces + printfs == 0)
        return SEQ_PLAIN;
    if (braces + printfs > 1)
        return SEQ_INVALID;
    return braces ? SEQ_BRACES : SEQ_PRINTF;
}

seq_kind seq_kind_of(const char *s)
{
    size_t at = 0, len = 0;
    int w = 0, z = 0;
    return find_placeholder(s, &at, &len, &w, &z);
}

int seq_is_template(const char *s)
{
    seq_kind k = seq_kind_of(s);
    return k == SEQ_BRACES || k == SEQ_PRINTF;
}

int seq_natural_cmp(const char *a, const char *b)
{
    const unsigned char *p = (const unsigned char *)a, *q = (const unsigned char *)b;
    while (*p && *q) {
        if (isdigit(*p) && isdigit(*q)) {
            while (*p == '0' && isdigit(p[1]))
                p++;
            while (*q == '0' && isdigit(q[1]))
                q++;
            size_t lp = 0, lq = 0;
            while (isdigit(p[lp]))
                lp++;
            while (isdigit(q[lq]))
                lq++;
            if (lp != lq)
                return lp < lq ? -1 : 1;
            int c = memcmp(p, q, lp);
            if (c != 0)
                return c < 0 ? -1 : 1;
            p += lp;
            q += lq;
        } else {
            if (*p != *q)
                return *p < *q ? -1 : 1;
            p++;
            q++;
        }
    }
    if (*p || *q)
        return *p ? 1 : -1;
    int c = strcmp(a, b); /* equal by value: "01" vs "1" */
    return c < 0 ? -1 : c > 0;
}

static const char *base_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

char *seq_stem(const char *path)
{
    const char *base = base_of(path);
    size_t len = strlen(base);
    if (len > 3 && strcmp(base + len - 3, ".gz") == 0)
        len -= 3;
    for (size_t i = len; i > 1; i--) {
        if (base[i - 1] == '.') {
            len = i - 1;
            break;
        }
    }
    char *s = malloc(len + 1);
    if (s) {
        memcpy(s, base, len);
        s[len] = 0;
    }
    return s;
}

int seq_number_in_name(const char *path, long *index, char **digits)
{
    char *stem = seq_stem(path);
    if (!stem)
        return 0;
    size_t len = strlen(stem), begin = 0, end = 0;
    /* "frame" (any case), one optional separator, digits: the last such */
    for (size_t i = 0; i + 5 <= len; i++) {
        static const char word[] = "frame";
        size_t k = 0;
        while (k < 5 && tolower((unsigned char)stem[i + k]) == word[k])
            k++;
        if (k < 5)
            continue;
        size_t j = i + 5;
        if (j < len && (stem[j] == '_' || stem[j] == '-' || stem[j] == '.' || stem[j] == ' '))
            j++;
        size_t e = j;
        while (e < len && isdigit((unsigned char)stem[e]))
            e++;
        if (e > j) {
            begin = j;
            end = e;
        }
    }
    if (end == 0) { /* else the last run of digits */
        end = len;
        while (end > 0 && !isdigit((unsigned char)stem[end - 1]))
            end--;
        begin = end;
        while (begin > 0 && isdigit((unsigned char)stem[begin - 1]))
            begin--;
    }
    long v = 0;
    int found = end > begin && parse_index(stem + begin, end - begin, &v) == 0;
    if (found) {
        char *d = malloc(end - begin + 1);
        if (!d) {
            free(stem);
            return 0;
        }
        memcpy(d, stem + begin, end - begin);
        d[end - begin] = 0;
        *index = v;
        *digits = d;
    }
    free(stem);
    return found;
}

int seq_list_add(seq_list *l, const char *path, long index, const char *digits)
{
    if (l->count == l->cap) {
        size_t cap = l->cap ? l->cap * 2 : 16;
        seq_frame *n = realloc(l->items, cap * sizeof *n);
        if (!n)
            return -1;
        l->items = n;
        l->cap = cap;
    }
    seq_frame *f = &l->items[l->count];
    f->path = seq_strdup(path);
    f->digits = digits ? seq_strdup(digits) : NULL;
    f->index = index;
    if (!f->path || (digits && !f->digits)) {
        free(f->path);
        free(f->digits);
        return -1;
    }
    l->count++;
    return 0;
}

void seq_list_free(seq_list *l)
{
    if (!l)
        return;
    for (size_t i = 0; i < l->count; i++) {
        free(l->items[i].path);
        free(l->items[i].digits);
    }
    free(l->items);
    memset(l, 0, sizeof *l);
}

/* Appends the text of s[0..len) to buf, turning "%%" into "%" if unescape. */
static size_t put_literal(char *buf, const char *s, size_t len, int unescape)
{
    size_t o = 0;
    for (size_t i = 0; i < len; i++) {
        if (unescape && s[i] == '%' && i + 1 < len && s[i + 1] == '%')
            i++;
        if (buf)
            buf[o] = s[i];
        o++;
    }
    return o;
}

char *seq_substitute(const char *tmpl, long index, const char *digits)
{
    size_t at = 0, len = 0;
    int width = 0, zero = 0;
    seq_kind k = find_placeholder(tmpl, &at, &len, &width, &zero);
    if (k != SEQ_BRACES && k != SEQ_PRINTF)
        return seq_strdup(tmpl);
    char num[160];
    if (k == SEQ_BRACES && digits)
        snprintf(num, sizeof num, "%s", digits);
    else if (k == SEQ_PRINTF && zero)
        snprintf(num, sizeof num, "%0*ld", width, index);
    else if (k == SEQ_PRINTF)
        snprintf(num, sizeof num, "%*ld", width, index);
    else
        snprintf(num, sizeof num, "%ld", index);
    int unesc = k == SEQ_PRINTF;
    const char *rest = tmpl + at + len;
    size_t n = put_literal(NULL, tmpl, at, unesc) + strlen(num) +
               put_literal(NULL, rest, strlen(rest), unesc);
    char *out = malloc(n + 1);
    if (!out)
        return NULL;
    size_t o = put_literal(out, tmpl, at, unesc);
    memcpy(out + o, num, strlen(num));
    o += strlen(num);
    o += put_literal(out + o, rest, strlen(rest), unesc);
    out[o] = 0;
    return out;
}

char *seq_in_directory(const char *dir, const char *input, const char *ext)
{
    char *stem = seq_stem(input);
    if (!stem)
        return NULL;
    size_t dl = strlen(dir);
    if (dl == 0) {
        dir = ".";
        dl = 1;
    }
    while (dl > 1 && dir[dl - 1] == '/')
        dl--;
    size_t n = dl + 1 + strlen(stem) + 1 + strlen(ext) + 1;
    char *out = malloc(n);
    if (out)
        snprintf(out, n, "%.*s%s%s.%s", (int)dl, dir, dir[dl - 1] == '/' ? "" : "/", stem, ext);
    free(stem);
    return out;
}

typedef struct match {
    char *name;
    long index;
} match;

static int match_cmp(const void *a, const void *b)
{
    const match *x = a, *y = b;
    if (x->index != y->index)
        return x->index < y->index ? -1 : 1;
    return seq_natural_cmp(x->name, y->name);
}

static int is_regular(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* Scans the directory of pattern for files that match it. */
static int expand_scan(const char *pattern, seq_kind kind, size_t at, size_t len,
                       const seq_range *range, seq_list *out, char *err, size_t errlen)
{
    const char *base = base_of(pattern);
    size_t dirlen = (size_t)(base - pattern); /* with the trailing '/' */
    if (at < dirlen) {
        seq_err(err, errlen, "'%s': the frame placeholder must be in the file name, not the directory",
                pattern);
        return -1;
    }
    char *dir = malloc(dirlen + 2);
    if (!dir) {
        seq_err(err, errlen, "out of memory");
        return -1;
    }
    if (dirlen == 0)
        strcpy(dir, ".");
    else {
        memcpy(dir, pattern, dirlen);
        dir[dirlen] = 0;
    }
    int unesc = kind == SEQ_PRINTF;
    const char *pre = base, *suf = pattern + at + len;
    size_t prelen = (size_t)(pattern + at - base);
    char *prefix = malloc(prelen + 1), *suffix = malloc(strlen(suf) + 1);
    if (!prefix || !suffix) {
        free(dir), free(prefix), free(suffix);
        seq_err(err, errlen, "out of memory");
        return -1;
    }
    prefix[put_literal(prefix, pre, prelen, unesc)] = 0;
    suffix[put_literal(suffix, suf, strlen(suf), unesc)] = 0;

    DIR *d = opendir(dir);
    if (!d) {
        seq_err(err, errlen, "%s: cannot list directory for '%s': %s", dir, pattern, strerror(errno));
        free(dir), free(prefix), free(suffix);
        return -1;
    }
    match *m = NULL;
    size_t nm = 0, cap = 0;
    int rc = 0;
    struct dirent *e;
    size_t pl = strlen(prefix), sl = strlen(suffix);
    while ((e = readdir(d)) != NULL) {
        const char *name = e->d_name;
        size_t nl = strlen(name);
        if (nl <= pl + sl || strncmp(name, prefix, pl) != 0 || strcmp(name + nl - sl, suffix) != 0)
            continue;
        long idx;
        if (parse_index(name + pl, nl - pl - sl, &idx) != 0)
            continue;
        if (kind == SEQ_PRINTF) { /* the pattern must print the name back exactly */
            char *again = seq_substitute(base, idx, NULL);
            int same = again && strcmp(again, name) == 0;
            free(again);
            if (!same)
                continue;
        }
        if (!seq_range_contains(range, idx))
            continue;
        char *full = malloc(dirlen + nl + 1);
        if (!full) {
            rc = -1;
            break;
        }
        memcpy(full, pattern, dirlen);
        memcpy(full + dirlen, name, nl + 1);
        if (!is_regular(full)) {
            free(full);
            continue;
        }
        if (nm == cap) {
            size_t nc = cap ? cap * 2 : 64;
            match *n2 = realloc(m, nc * sizeof *n2);
            if (!n2) {
                free(full);
                rc = -1;
                break;
            }
            m = n2;
            cap = nc;
        }
        m[nm].name = full;
        m[nm].index = idx;
        nm++;
    }
    closedir(d);
    if (rc != 0)
        seq_err(err, errlen, "out of memory");
    if (rc == 0 && nm == 0) {
        if (range && range->set)
            seq_err(err, errlen, "no files match '%s' in the frames %ld:%ld:%ld", pattern,
                    range->start, range->end, range->step);
        else
            seq_err(err, errlen, "no files match '%s'", pattern);
        rc = -1;
    }
    if (rc == 0) {
        qsort(m, nm, sizeof *m, match_cmp);
        for (size_t i = 0; i < nm && rc == 0; i++) {
            const char *nb = base_of(m[i].name);
            size_t dl = strlen(nb) - pl - sl;
            char digits[32];
            snprintf(digits, sizeof digits, "%.*s", (int)dl, nb + pl);
            if (seq_list_add(out, m[i].name, m[i].index, digits) != 0) {
                seq_err(err, errlen, "out of memory");
                rc = -1;
            }
        }
    }
    for (size_t i = 0; i < nm; i++)
        free(m[i].name);
    free(m);
    free(dir), free(prefix), free(suffix);
    return rc;
}

int seq_expand(char *const *inputs, size_t n, const seq_range *range,
               seq_list *out, char *err, size_t errlen)
{
    for (size_t i = 0; i < n; i++) {
        const char *in = inputs[i];
        size_t at = 0, len = 0;
        int width = 0, zero = 0;
        seq_kind k = find_placeholder(in, &at, &len, &width, &zero);
        if (k != SEQ_PLAIN && is_regular(in))
            k = SEQ_PLAIN; /* a file really named like a pattern */
        if (k == SEQ_INVALID) {
            seq_err(err, errlen, "'%s': more than one frame placeholder ({} or %%d)", in);
            return -1;
        }
        if (k == SEQ_PLAIN) {
            long idx = (long)i;
            char *digits = NULL;
            seq_number_in_name(in, &idx, &digits);
            int rc = 0;
            if (seq_range_contains(range, idx))
                rc = seq_list_add(out, in, idx, digits);
            free(digits);
            if (rc != 0) {
                seq_err(err, errlen, "out of memory");
                return -1;
            }
        } else if (k == SEQ_PRINTF && range && range->set) {
            if (at < (size_t)(base_of(in) - in)) {
                seq_err(err, errlen,
                        "'%s': the frame placeholder must be in the file name, not the directory", in);
                return -1;
            }
            if ((range->end - range->start) / range->step >= SEQ_MAX_FRAMES) {
                seq_err(err, errlen,
                        "'%s': --frames %ld:%ld:%ld names %ld frames, more than the %d one run plans: "
                        "split the range over several runs (--frames) or shards (--shard)",
                        in, range->start, range->end, range->step,
                        (range->end - range->start) / range->step + 1, SEQ_MAX_FRAMES);
                return -1;
            }
            for (long f = range->start; f <= range->end; f += range->step) {
                char num[32];
                snprintf(num, sizeof num, zero ? "%0*ld" : "%*ld", width, f);
                char *path = seq_substitute(in, f, NULL);
                int rc = path ? seq_list_add(out, path, f, num) : -1;
                free(path);
                if (rc != 0) {
                    seq_err(err, errlen, "out of memory");
                    return -1;
                }
                if (range->end - f < range->step)
                    break;
            }
        } else if (expand_scan(in, k, at, len, range, out, err, errlen) != 0) {
            return -1;
        }
    }
    return 0;
}
