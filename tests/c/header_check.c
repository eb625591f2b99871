/* Compiled as C99 and as C11 with -Wall -Wextra -pedantic -Werror: the public header must be
 * clean for every C compiler mode users build with. */
#include <gfmd.h>

int main(void) {
    gfmd_sim *s = 0;
    int32_t st = gfmd_sim_create(4, 4, 1.0, 1.0, &s);
    gfmd_sim_destroy(&s);
    return st == GFMD_OK && GFMD_VERSION_NUMBER >= 100 ? 0 : 1;
}
