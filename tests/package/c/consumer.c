/* A user's program against the installed library: version agreement and one real relaxation. */
#include <gfmd.h>
#include <stdio.h>
#include <string.h>

int main(void) {
    if (strcmp(gfmd_version(), GFMD_VERSION_STRING) != 0) {
        fprintf(stderr, "header %s, library %s\n", GFMD_VERSION_STRING, gfmd_version());
        return 1;
    }
    gfmd_sim *s = NULL;
    double area = 0.0;
    if (gfmd_sim_create(64, 64, 64.0, 64.0, &s) != GFMD_OK) return 1;
    if (gfmd_generate_selfaffine(s, 0.8, 16.0, 4.0, 1.0, 1, GFMD_DIST_UNIFORM) != GFMD_OK) return 1;
    if (gfmd_set_pressure(s, 0.05) != GFMD_OK) return 1;
    if (gfmd_relax(s, 0.0, 100000, NULL) != GFMD_OK) return 1;
    gfmd_get_contact_area(s, &area);
    gfmd_sim_destroy(&s);
    printf("consumer: gfmd %s, A/A0 = %.4f\n", gfmd_version(), area);
    return (area > 0.0 && area < 1.0) ? 0 : 1;
}
