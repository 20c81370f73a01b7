/* exr_writer_thread.c: exr_writer, the background threads that write queued frames with
 * exr_write_file_quiet (exr_write.c), one path at a time. See exr_write.h. */
#include "output/exr_internal.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "core/config.h"
#include "core/log.h"

typedef struct exr_job {
    char *path;
    exr_image img;
} exr_job;

typedef struct exr_worker {
    pthread_t thread;
    exr_writer *w;
    const char *busy_path; /* the path it is writing, NULL when idle; guarded by w->mu */
} exr_worker;

/* Jobs leave the ring in submission order. A worker takes the oldest job unless another worker
 * is still writing that job's path: then every worker waits (the queue head blocks) until that
 * write is done, and the worker that did it takes the job. So writes to one path never overlap
 * and the last one submitted is what stays on disk, as with a single thread. */
struct exr_writer {
    pthread_mutex_t mu;
    pthread_cond_t not_empty; /* the oldest job may be free to take, or stop was set */
    pthread_cond_t not_full;  /* a job was taken off the queue, or err was set */
    exr_compression_kind compression;
    int zip_level;
    exr_job *ring; /* queue_depth slots */
    int queue_depth, head, count;
    exr_worker *workers; /* thread_count slots; the first `started` run */
    int thread_count, started;
    bool stop;     /* set by finish: drain the queue, then exit */
    fs_status err; /* first failure, sticky */
    double cpu_s;  /* the exited workers' CPU time */
    double *cpu_out;
};

exr_writer_desc exr_writer_desc_defaults(const exr_writer_desc *d)
{
    exr_writer_desc r = d ? *d : (exr_writer_desc){0};
    if (r.compression != EXR_COMPRESS_NONE && r.compression != EXR_COMPRESS_PIZ)
        r.compression = EXR_COMPRESS_ZIP;
    if (r.queue_depth <= 0)
        r.queue_depth = EXR_QUEUE_DEPTH;
    if (r.thread_count <= 0) {
        long n = sysconf(_SC_NPROCESSORS_ONLN); /* -1 when unknown */
        r.thread_count = n > EXR_MAX_WRITER_THREADS ? EXR_MAX_WRITER_THREADS : n < 1 ? 1 : (int)n;
    }
    if (r.thread_count > EXR_MAX_WRITER_THREADS)
        r.thread_count = EXR_MAX_WRITER_THREADS;
    r.zip_level = exr_clamp_zip_level(r.zip_level);
    return r;
}

static bool path_in_flight(const exr_writer *w, const char *path)
{
    for (int i = 0; i < w->thread_count; i++)
        if (w->workers[i].busy_path && strcmp(w->workers[i].busy_path, path) == 0)
            return true;
    return false;
}

static void *writer_main(void *arg)
{
    exr_worker *me = arg;
    exr_writer *w = me->w;
    pthread_mutex_lock(&w->mu);
    for (;;) {
        while ((w->count == 0 && !w->stop) ||
               (w->count > 0 && path_in_flight(w, w->ring[w->head].path)))
            pthread_cond_wait(&w->not_empty, &w->mu);
        if (w->count == 0) {
            /* Stop requested and queue drained. Others may still be waiting for a path that was
             * busy when finish woke them: they must see this too. */
            pthread_cond_broadcast(&w->not_empty);
            break;
        }
        exr_job job = w->ring[w->head];
        memset(&w->ring[w->head], 0, sizeof w->ring[w->head]);
        w->head = (w->head + 1) % w->queue_depth;
        w->count--;
        me->busy_path = job.path;
        pthread_cond_signal(&w->not_full);
        /* Pass the wake-up on: the new oldest job may be free for an idle worker. (A worker that
         * finishes a write needs no wake-up: it loops and takes the head itself.) */
        if (w->count > 0)
            pthread_cond_signal(&w->not_empty);
        pthread_mutex_unlock(&w->mu);

        /* Jobs accepted before a failure are still written: each write is atomic, so a complete
         * frame is never worse than none. */
        char err[1600];
        fs_status st = exr_write_file_quiet(job.path, &job.img, w->compression, w->zip_level, err, sizeof err);
        exr_image_free(&job.img);

        pthread_mutex_lock(&w->mu);
        me->busy_path = NULL;
        free(job.path); /* only after busy_path no longer points at it */
        if (st != FS_OK && w->err == FS_OK) {
            log_error("%s", err); /* the first failure only: the run stops on it */
            w->err = st;
            pthread_cond_broadcast(&w->not_full); /* blocked submitters return the error */
        }
    }
    struct timespec ts;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) == 0)
        w->cpu_s += (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
    pthread_mutex_unlock(&w->mu);
    return NULL;
}

/* Stops the started workers (after they drain the queue), frees everything and returns the first
 * error. */
static fs_status writer_shutdown(exr_writer *w)
{
    pthread_mutex_lock(&w->mu);
    w->stop = true;
    pthread_cond_broadcast(&w->not_empty);
    pthread_mutex_unlock(&w->mu);
    for (int i = 0; i < w->started; i++)
        pthread_join(w->workers[i].thread, NULL);
    fs_status st = w->err; /* every worker has been joined: no lock needed */
    if (w->cpu_out)
        *w->cpu_out = w->cpu_s;
    pthread_cond_destroy(&w->not_full);
    pthread_cond_destroy(&w->not_empty);
    pthread_mutex_destroy(&w->mu);
    free(w->workers);
    free(w->ring);
    free(w);
    return st;
}

exr_writer *exr_writer_create(const exr_writer_desc *desc)
{
    exr_writer_desc d = exr_writer_desc_defaults(desc);
    exr_writer *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    w->ring = calloc((size_t)d.queue_depth, sizeof *w->ring);
    w->workers = calloc((size_t)d.thread_count, sizeof *w->workers);
    if (!w->ring || !w->workers)
        goto fail_mu;
    w->queue_depth = d.queue_depth;
    w->thread_count = d.thread_count;
    w->compression = d.compression;
    w->zip_level = d.zip_level;
    w->cpu_out = d.cpu_seconds;
    w->err = FS_OK;
    if (pthread_mutex_init(&w->mu, NULL) != 0)
        goto fail_mu;
    if (pthread_cond_init(&w->not_empty, NULL) != 0)
        goto fail_ne;
    if (pthread_cond_init(&w->not_full, NULL) != 0)
        goto fail_nf;
    for (int i = 0; i < d.thread_count; i++) {
        w->workers[i].w = w;
        if (pthread_create(&w->workers[i].thread, NULL, writer_main, &w->workers[i]) != 0)
            break;
        w->started++;
    }
    if (w->started == 0) {
        (void)writer_shutdown(w);
        return NULL;
    }
    /* Fewer threads (a process or system thread limit) are slower, not wrong. */
    if (w->started < d.thread_count)
        log_warn("EXR: started %d of %d writer threads", w->started, d.thread_count);
    return w;

fail_nf:
    pthread_cond_destroy(&w->not_empty);
fail_ne:
    pthread_mutex_destroy(&w->mu);
fail_mu:
    free(w->workers);
    free(w->ring);
    free(w);
    return NULL;
}

fs_status exr_writer_submit(exr_writer *w, const char *path, exr_image *img)
{
    FS_ASSERT(w && path && img);
    char *path_copy = strdup(path);
    pthread_mutex_lock(&w->mu);
    FS_ASSERT(!w->stop);
    while (w->count == w->queue_depth && w->err == FS_OK)
        pthread_cond_wait(&w->not_full, &w->mu);
    fs_status st = w->err;
    if (st == FS_OK && !path_copy) {
        log_error("%s: cannot queue EXR write: out of memory", path);
        st = FS_ERR_NOMEM;
    }
    if (st == FS_OK) {
        /* count < queue_depth here: either it was below, or err is set (handled above). */
        int tail = (w->head + w->count) % w->queue_depth;
        w->ring[tail].path = path_copy;
        w->ring[tail].img = *img; /* the planes move to the queue */
        w->count++;
        pthread_cond_signal(&w->not_empty);
    }
    pthread_mutex_unlock(&w->mu);
    if (st == FS_OK) {
        memset(img, 0, sizeof *img);
    } else {
        free(path_copy);
        exr_image_free(img);
    }
    return st;
}

fs_status exr_writer_finish(exr_writer *w)
{
    if (!w)
        return FS_OK;
    return writer_shutdown(w);
}
