/* Screenshots (viewer/screenshot.h): OpenGL's rows run bottom to top, a
 * PNG's top to bottom: stb flips them as it writes. */
#include "viewer/screenshot.h"
#include "common/error.h"

#include <epoxy/gl.h>
#include <errno.h>
#include <stb/stb_image_write.h>
#include <stdlib.h>
#include <string.h>

sb_status sb_screenshot_save(const char* path, int width, int height, sb_error* err) {
    size_t row = 3 * (size_t)width;
    unsigned char* pixels = malloc(row * (size_t)height + 1);
    if (!pixels) return sb_error_set(err, SB_ERR_NOMEM, "view: out of memory for the screenshot");
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels);
    errno = 0;
    stbi_flip_vertically_on_write(1);
    int ok = stbi_write_png(path, width, height, 3, pixels, (int)row);
    free(pixels);
    return ok ? SB_OK : sb_error_at(err, SB_ERR_IO, path, 0, "cannot write: %s", errno ? strerror(errno) : "failed");
}
