/* Saving what the viewer drew: the framebuffer as a PNG (stb_image_write,
 * Debian's libstb-dev). */
#ifndef SB_VIEWER_SCREENSHOT_H
#define SB_VIEWER_SCREENSHOT_H

#include "softbond/types.h"

/* The current framebuffer (width × height, RGB) to path. */
sb_status sb_screenshot_save(const char* path, int width, int height, sb_error* err);

#endif
