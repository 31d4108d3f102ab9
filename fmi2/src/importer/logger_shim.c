/* fmi2CallbackLogger for the importer: formats the message (the FMU chooses the format) and passes
 * it to the Rust sink stored first in the component environment. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

typedef void (*airring_sink_fn)(void *env, const char *instance, int status, const char *category, const char *message);

struct airring_log_env {
    airring_sink_fn sink; /* first field; the rest belongs to Rust */
};

void airring_fmi2_logger(void *env, const char *instance, int status, const char *category, const char *format, ...) {
    struct airring_log_env *e = (struct airring_log_env *)env;
    if (e == NULL || e->sink == NULL || format == NULL) {
        return;
    }
    char small[1024];
    va_list ap;
    va_start(ap, format);
    int n = vsnprintf(small, sizeof small, format, ap);
    va_end(ap);
    if (n < 0) {
        e->sink(env, instance, status, category, format);
        return;
    }
    if ((size_t)n < sizeof small) {
        e->sink(env, instance, status, category, small);
        return;
    }
    char *big = (char *)malloc((size_t)n + 1);
    if (big == NULL) {
        e->sink(env, instance, status, category, small);
        return;
    }
    va_start(ap, format);
    vsnprintf(big, (size_t)n + 1, format, ap);
    va_end(ap);
    e->sink(env, instance, status, category, big);
    free(big);
}
