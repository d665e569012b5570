/* Screenshots (viewer/screenshot.h): OpenGL's rows run bottom to top, a
 * PNG's top to bottom: stb flips them as it writes. The PNG goes through
 * an atomic file (common/atomic_file.h): every write is checked, and a
 * failed one (a full disk, /dev/full) leaves nothing under the name. */
#include "viewer/screenshot.h"
#include "common/atomic_file.h"
#include "common/error.h"

#include <epoxy/gl.h>
#include <errno.h>
#include <stb/stb_image_write.h>
#include <stdlib.h>
#include <string.h>

typedef struct png_sink {
    FILE* stream;
    int error; /* errno of the first failed write, 0 = none */
} png_sink;

static void put(void* context, void* data, int size) {
    png_sink* sink = context;
    errno = 0;
    if (size > 0 && fwrite(data, 1, (size_t)size, sink->stream) != (size_t)size && !sink->error)
        sink->error = errno ? errno : EIO;
}

sb_status sb_screenshot_save(const char* path, int width, int height, sb_error* err) {
    size_t row = 3 * (size_t)width;
    unsigned char* pixels = malloc(row * (size_t)height + 1);
    if (!pixels) return sb_error_set(err, SB_ERR_NOMEM, "view: out of memory for the screenshot");
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels);
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status == SB_OK) {
        png_sink sink = {file.stream, 0};
        stbi_flip_vertically_on_write(1);
        int encoded = stbi_write_png_to_func(put, &sink, width, height, 3, pixels, (int)row);
        if (encoded && !sink.error)
            status = sb_atomic_commit(&file, err);
        else {
            sb_atomic_abort(&file);
            status = sink.error ? sb_error_set(err, SB_ERR_IO, "%s: cannot write: %s", path, strerror(sink.error))
                                : sb_error_set(err, SB_ERR_IO, "%s: cannot write: the PNG could not be encoded", path);
        }
    }
    free(pixels);
    return status;
}
