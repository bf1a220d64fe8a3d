/* examples/process/step.c with two mistakes put in (those of examples/buggy_sim.py), for the
   diagnosis to find.

       cc -O2 -o buggy_step examples/process/buggy_step.c -lm
       python -m compare validate --sim-process ./buggy_step box_drop

   Mistake 1: friction acts on the velocity of the centre of mass, vx, instead of the slip
              velocity of the contact point, vx - omega r_y.
   Mistake 2: the box's inertia is m (w^2 + h^2) / 3 (about a corner) instead of / 12.

   The harness writes `scene {JSON}` (the dict `python -m compare scene SCENE --json` prints, on
   one line); this program answers `ready scene` (it steps with the scene's integrator) or
   `skip REASON`. Then each `step DT X Y THETA VX VY OMEGA` line is answered with the state one
   step DT later, six numbers at 17 significant digits. See docs/process-protocol.md. */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_POINTS 64
#define MAX_PARTS 16

typedef struct {
    char integrator[64], damping_law[32], friction_law[32], roll_law[32];
    int gravity, contact, friction, rolling;         /* the scene's effects */
    double g, k, c, mu, alpha, mu_roll, roll_sharpness;
    double mass, inertia;
    int points_rotate, rotates, n_points;
    double points[MAX_POINTS][2];                    /* contact points relative to the centre of mass */
    char shape[32];                                  /* what the wrong inertia is made of */
    double body_mass, size[2], com[2];
    int n_parts;
    double part_mass[MAX_PARTS], part_size[MAX_PARTS][2], part_offset[MAX_PARTS][2];
} Scene;

static Scene S;

/* ---- a small JSON reader: every scalar is handed over with its path, e.g. ".contact.k" ---- */

static const char *at;

static void spaces(void) { while (isspace((unsigned char)*at)) at++; }

static void on_number(const char *path, double v) {
    int i, j;
    if (!strcmp(path, ".g")) S.g = v;
    else if (!strcmp(path, ".contact.k")) S.k = v;
    else if (!strcmp(path, ".contact.c")) S.c = v;
    else if (!strcmp(path, ".contact.mu")) S.mu = v;
    else if (!strcmp(path, ".contact.alpha")) S.alpha = v;
    else if (!strcmp(path, ".contact.mu_roll")) S.mu_roll = v;
    else if (!strcmp(path, ".contact.roll_sharpness")) S.roll_sharpness = v;
    else if (!strcmp(path, ".mass_properties.mass")) S.mass = v;
    else if (!strcmp(path, ".mass_properties.inertia")) S.inertia = v;
    else if (!strcmp(path, ".mass_properties.points_rotate")) S.points_rotate = v != 0.0;
    else if (!strcmp(path, ".mass_properties.rotates")) S.rotates = v != 0.0;
    else if (!strcmp(path, ".body.mass")) S.body_mass = v;
    else if (sscanf(path, ".body.size.%d", &i) == 1 && i < 2) S.size[i] = v;
    else if (sscanf(path, ".mass_properties.com.%d", &i) == 1 && i < 2) S.com[i] = v;
    else if (sscanf(path, ".body.parts.%d.mass", &i) == 1 && i < MAX_PARTS && !strcmp(path + strlen(path) - 5, ".mass")) {
        S.part_mass[i] = v;
        if (i + 1 > S.n_parts) S.n_parts = i + 1;
    }
    else if (sscanf(path, ".body.parts.%d.size.%d", &i, &j) == 2 && i < MAX_PARTS && j < 2) S.part_size[i][j] = v;
    else if (sscanf(path, ".body.parts.%d.offset.%d", &i, &j) == 2 && i < MAX_PARTS && j < 2) S.part_offset[i][j] = v;
    else if (sscanf(path, ".mass_properties.contact_points.%d.%d", &i, &j) == 2 && i < MAX_POINTS && j < 2) {
        S.points[i][j] = v;
        if (i + 1 > S.n_points) S.n_points = i + 1;
    }
}

static void keep(char *out, size_t size, const char *s) {   /* s cut to fit out */
    size_t n = strlen(s) < size ? strlen(s) : size - 1;
    memcpy(out, s, n);
    out[n] = '\0';
}

static void on_string(const char *path, const char *s) {
    if (!strcmp(path, ".body.shape")) keep(S.shape, sizeof S.shape, s);
    else if (!strcmp(path, ".integrator")) keep(S.integrator, sizeof S.integrator, s);
    else if (!strcmp(path, ".contact.damping_law")) keep(S.damping_law, sizeof S.damping_law, s);
    else if (!strcmp(path, ".contact.friction_law")) keep(S.friction_law, sizeof S.friction_law, s);
    else if (!strcmp(path, ".contact.roll_law")) keep(S.roll_law, sizeof S.roll_law, s);
    else if (!strncmp(path, ".effects.", 9)) {
        if (!strcmp(s, "gravity")) S.gravity = 1;
        else if (!strcmp(s, "contact")) S.contact = 1;
        else if (!strcmp(s, "friction")) S.friction = 1;
        else if (!strcmp(s, "rolling_friction")) S.rolling = 1;
    }
}

static int string(char *out, size_t size) {           /* at the opening quote */
    size_t n = 0;
    at++;
    while (*at && *at != '"') {
        char ch = *at++;
        if (ch == '\\') {
            ch = *at++;
            if (ch == 'n') ch = '\n';
            else if (ch == 't') ch = '\t';
            else if (ch == 'u') { at += 4; ch = '?'; }   /* names here are ASCII */
        }
        if (n + 1 < size) out[n++] = ch;
    }
    out[n] = '\0';
    if (*at != '"') return 0;
    at++;
    return 1;
}

static int value(char *path, size_t len) {
    char text[4096];
    spaces();
    if (*at == '{' || *at == '[') {
        char close = *at == '{' ? '}' : ']';
        int index = 0;
        at++;
        spaces();
        if (*at == close) { at++; return 1; }
        for (;;) {
            spaces();
            if (close == '}') {
                if (*at != '"' || !string(text, sizeof text)) return 0;
                spaces();
                if (*at++ != ':') return 0;
                snprintf(path + len, 512 - len, ".%s", text);
            } else {
                snprintf(path + len, 512 - len, ".%d", index++);
            }
            if (!value(path, strlen(path))) return 0;
            path[len] = '\0';
            spaces();
            if (*at == ',') { at++; continue; }
            if (*at == close) { at++; return 1; }
            return 0;
        }
    }
    if (*at == '"') {
        if (!string(text, sizeof text)) return 0;
        on_string(path, text);
        return 1;
    }
    if (!strncmp(at, "true", 4)) { at += 4; on_number(path, 1.0); return 1; }
    if (!strncmp(at, "false", 5)) { at += 5; on_number(path, 0.0); return 1; }
    if (!strncmp(at, "null", 4)) { at += 4; return 1; }
    {
        char *end;
        double v = strtod(at, &end);
        if (end == at) return 0;
        at = end;
        on_number(path, v);
    }
    return 1;
}

/* ---- the physics: examples/buggy_sim.py, line for line ---- */

static double wrong_inertia(void) {              /* MISTAKE 2: a box's inertia about a corner, for every box */
    if (!strcmp(S.shape, "box"))
        return S.body_mass * (S.size[0] * S.size[0] + S.size[1] * S.size[1]) / 3.0;
    if (!strcmp(S.shape, "compound")) {
        double sum = 0.0;
        for (int i = 0; i < S.n_parts; i++) {
            double dx = S.part_offset[i][0] - S.com[0], dy = S.part_offset[i][1] - S.com[1];
            sum += S.part_mass[i] * (S.part_size[i][0] * S.part_size[i][0] + S.part_size[i][1] * S.part_size[i][1]) / 3.0
                   + S.part_mass[i] * (dx * dx + dy * dy);
        }
        return sum;
    }
    return S.inertia;
}

static void accelerations(const double z[6], double a[3]) {
    double x = z[0], y = z[1], theta = z[2], vx = z[3], vy = z[4], om = z[5];
    double fx = 0.0, fy = 0.0, tau = 0.0;
    (void)x;
    if (S.gravity) fy -= S.mass * S.g;                           /* F <- [0, -m g] */
    if (S.contact) {
        double c = S.points_rotate ? cos(theta) : 1.0, s = S.points_rotate ? sin(theta) : 0.0;
        for (int i = 0; i < S.n_points; i++) {
            double lx = S.points[i][0], ly = S.points[i][1];
            double rx = c * lx - s * ly, ry = s * lx + c * ly;   /* r_i <- R(theta) c_i^local */
            double d = -(y + ry);                                 /* depth below the ground y = 0 */
            if (d <= 0.0) continue;                               /* no force in the air */
            double vcx = vx, vcy = vy + om * rx;                  /* MISTAKE 1: slip taken as vx */
            double fn;
            if (!strcmp(S.damping_law, "compression"))
                fn = S.k * d + S.c * (-vcy > 0.0 ? -vcy : 0.0);  /* Algorithm 1, line 4 */
            else {
                fn = S.k * d - S.c * vcy;                         /* Kelvin-Voigt, never pulls */
                if (!(fn > 0.0)) fn = 0.0;
            }
            double ft = S.friction ? -S.mu * fn * tanh(S.alpha * vcx) : 0.0;
            fx += ft;
            fy += fn;
            tau += rx * fn - ry * ft;                             /* tau <- tau + r_i x F_i */
            if (S.rolling)                                        /* Algorithm 4, line 9 */
                tau -= S.mu_roll * fn * tanh(S.roll_sharpness * om);
        }
    }
    a[0] = fx / S.mass;
    a[1] = fy / S.mass;
    a[2] = S.rotates ? tau / wrong_inertia() : 0.0;
}

static void derivative(const double z[6], double d[6]) {
    double a[3];
    accelerations(z, a);
    d[0] = z[3]; d[1] = z[4]; d[2] = z[5]; d[3] = a[0]; d[4] = a[1]; d[5] = a[2];
}

static void step(double z[6], double dt) {
    double a[3], k1[6], k2[6], k3[6], k4[6], w[6];
    if (!strcmp(S.integrator, "semi_implicit_euler")) {           /* v <- v + a dt, then p <- p + v dt */
        accelerations(z, a);
        for (int i = 0; i < 3; i++) z[3 + i] = z[3 + i] + dt * a[i];
        for (int i = 0; i < 3; i++) z[i] = z[i] + dt * z[3 + i];
    } else if (!strcmp(S.integrator, "explicit_euler")) {         /* p <- p + v dt with the old v */
        derivative(z, k1);
        for (int i = 0; i < 6; i++) z[i] = z[i] + dt * k1[i];
    } else {                                                      /* rk4 */
        double h = 0.5 * dt, sixth = dt / 6.0;
        derivative(z, k1);
        for (int i = 0; i < 6; i++) w[i] = z[i] + h * k1[i];
        derivative(w, k2);
        for (int i = 0; i < 6; i++) w[i] = z[i] + h * k2[i];
        derivative(w, k3);
        for (int i = 0; i < 6; i++) w[i] = z[i] + dt * k3[i];
        derivative(w, k4);
        for (int i = 0; i < 6; i++) z[i] = z[i] + sixth * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
}

/* ---- the protocol ---- */

static void scene(const char *json) {
    char path[512] = "";
    memset(&S, 0, sizeof S);
    at = json;
    if (!value(path, 0)) {
        printf("skip cannot read the scene's JSON near: %.40s\n", at);
        return;
    }
    if (strcmp(S.integrator, "semi_implicit_euler") && strcmp(S.integrator, "explicit_euler")
        && strcmp(S.integrator, "rk4"))
        printf("skip integrator %s is not written in this example\n", S.integrator);
    else if (S.friction && strcmp(S.friction_law, "tanh"))
        printf("skip friction law %s is not written in this example (tanh only)\n", S.friction_law);
    else if (S.rolling && strcmp(S.roll_law, "tanh"))
        printf("skip rolling law %s is not written in this example (tanh only)\n", S.roll_law);
    else if (strcmp(S.damping_law, "compression") && strcmp(S.damping_law, "linear"))
        printf("skip damping law %s is not written in this example\n", S.damping_law);
    else if (S.n_points > MAX_POINTS - 1)
        printf("skip more than %d contact points\n", MAX_POINTS - 1);
    else
        printf("ready scene\n");
}

int main(void) {
    char *line = NULL;
    size_t size = 0;
    while (getline(&line, &size, stdin) > 0) {
        if (!strncmp(line, "scene ", 6)) {
            scene(line + 6);
        } else if (!strncmp(line, "step ", 5)) {
            double dt, z[6];
            char *p = line + 5, *end;
            dt = strtod(p, &end);
            for (int i = 0; i < 6; i++) { p = end; z[i] = strtod(p, &end); }
            step(z, dt);
            printf("%.17g %.17g %.17g %.17g %.17g %.17g\n", z[0], z[1], z[2], z[3], z[4], z[5]);
        } else {
            fprintf(stderr, "buggy_step.c: expected a `scene` or `step` line, got: %s", line);
            return 2;
        }
        fflush(stdout);
    }
    free(line);
    return 0;
}
