/* progress.c - draws and erases the terminal progress bar of a multi-frame conversion. */
#include "progress.h"

#include <stdio.h>
#include <unistd.h>

#include "platform.h"

void progress_init(progress *p, size_t total, int want)
{
    p->enabled = want && isatty(STDERR_FILENO);
    p->total = total;
    p->done = 0;
    p->start_ms = platform_now_ms();
    p->last_draw_ms = -1e9;
    p->drawn = 0;
}

static void draw(progress *p)
{
    const int width = 30;
    double now = platform_now_ms();
    double secs = (now - p->start_ms) / 1000.0;
    double rate = secs > 0 && p->done > 0 ? (double)p->done / secs : 0;
    int fill = p->total ? (int)((double)width * (double)p->done / (double)p->total) : width;
    char bar[64];
    for (int i = 0; i < width; i++)
        bar[i] = i < fill ? '=' : (i == fill ? '>' : ' ');
    bar[width] = 0;
    char eta[32] = "--:--";
    if (rate > 0) {
        long left = (long)((double)(p->total - p->done) / rate + 0.5);
        snprintf(eta, sizeof eta, "%ld:%02ld", left / 60, left % 60);
    }
    fprintf(stderr, "\r[%s] %zu/%zu frames  %.1f frames/s  ETA %s\033[K", bar, p->done, p->total,
            rate, eta);
    fflush(stderr);
    p->drawn = 1;
    p->last_draw_ms = now;
}

void progress_update(progress *p, size_t done)
{
    if (!p->enabled)
        return;
    p->done = done;
    double now = platform_now_ms();
    if (now - p->last_draw_ms >= 100.0 || done == p->total)
        draw(p);
}

void progress_clear(progress *p)
{
    if (!p->enabled || !p->drawn)
        return;
    fputs("\r\033[K", stderr);
    fflush(stderr);
    p->drawn = 0;
}

void progress_redraw(progress *p)
{
    if (p->enabled)
        draw(p);
}

void progress_finish(progress *p)
{
    progress_clear(p);
    p->enabled = 0;
}
