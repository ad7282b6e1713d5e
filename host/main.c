/* gmonrt: placeholder until the renderer exists (issue: path tracer). */
#include <stdio.h>

int main(void)
{
    fprintf(stderr, "gmonrt: the renderer is not implemented yet\n");
    return 1;
}
