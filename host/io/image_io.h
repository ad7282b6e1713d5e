/* What the image writers and readers in host/io return. On failure they also
 * put one line naming the file and the cause in the caller's error buffer. */
#ifndef HOST_IO_IMAGE_IO_H
#define HOST_IO_IMAGE_IO_H

typedef enum {
    IMAGE_IO_OK = 0,
    IMAGE_IO_ERROR = 1,
} ImageIoStatus;

#endif
