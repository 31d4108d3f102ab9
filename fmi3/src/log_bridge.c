/* The fmi2 instance logs through a C-variadic fmi2CallbackLogger, which stable Rust can call but not
 * define. This bridge is that logger: it formats the message and hands it to the Rust sink whose
 * address is the component environment (see logging.rs, LogSink). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

typedef struct airring_fmi3_sink {
    /* First field of the #[repr(C)] LogSink; the rest is opaque here. */
    void (*forward)(const struct airring_fmi3_sink *sink, int status, const char *category,
                    const char *message);
} airring_fmi3_sink;

void airring_fmi3_log_bridge(void *environment, const char *instance_name, int status,
                             const char *category, const char *format, ...) {
    const airring_fmi3_sink *sink = (const airring_fmi3_sink *)environment;
    va_list args, copy;
    int n;
    char *message;
    (void)instance_name; /* FMI 3.0 messages carry no instance name: the environment identifies it. */
    if (sink == NULL || sink->forward == NULL || format == NULL) {
        return;
    }
    va_start(args, format);
    va_copy(copy, args);
    n = vsnprintf(NULL, 0, format, args);
    va_end(args);
    message = n < 0 ? NULL : (char *)malloc((size_t)n + 1);
    if (message != NULL) {
        vsnprintf(message, (size_t)n + 1, format, copy);
        sink->forward(sink, status, category, message);
        free(message);
    }
    va_end(copy);
}
