/*
 * The FINken rigid-body quadrotor (nps_finken_quadrotor): hover equilibrium, free fall (with and without drag), the
 * yaw and roll responses to rotor torques, rotor lag, the ground, energy and angular momentum, the accelerometer,
 * and a closed loop (a reference controller in this file) whose velocity step response is compared with the host's
 * first-order lag model (nps_finken_lag). Expected values are worked out by hand in the comments (FINken defaults:
 * m = 0.5 kg, T_max = 3 N per rotor, k = 0.01 m, l = 0.12 m, Ixx = Iyy = 1.5e-3, Izz = 2.8e-3 kg m^2, g = 9.81).
 * Deterministic: tolerances are the integrator's error (classical Runge-Kutta, error per step O(dt^5)), stated per test.
 */
#include "test_helpers.h"
#include "nps_finken_quadrotor.h"
#include "nps_finken_lag.h"

#include <string.h>

#define DT (1.0 / 512.0)   /* Paparazzi's NPS step for a 512 Hz rotorcraft */

static struct nps_finken_quadrotor_params finken(void)
{
  struct nps_finken_quadrotor_params p;
  nps_finken_quadrotor_params_default(&p);
  return p;
}

/** In flight at height h [m] (NED z = -h), level, heading 0, rotors at speed w. */
static struct nps_finken_quadrotor_state flying(double h, double w)
{
  struct nps_finken_quadrotor_state s;
  nps_finken_quadrotor_init(&s, 0.0, 0.0, 0.0);
  s.pos_m[2] = -h;
  s.on_ground = false;
  for (int i = 0; i < NPS_FINKEN_QUADROTOR_ROTORS; i++) {
    s.rotor_speed[i] = w;
  }
  return s;
}

static void run(struct nps_finken_quadrotor_state *s, const struct nps_finken_quadrotor_params *p, const double c[4],
                const double *wind, double t_s)
{
  const long n = lround(t_s / DT);
  for (long i = 0; i < n; i++) {
    nps_finken_quadrotor_step(s, p, c, wind, DT);
  }
}

static void defaults_are_the_finken_estimates(void **state)
{
  (void)state;
  const struct nps_finken_quadrotor_params p = finken();
  assert_close(p.mass_kg, 0.5, 0.0);
  /* QUAD_X: front left (CW), front right (CCW), back right (CW), back left (CCW), at l / sqrt(2) on each axis */
  const double a = 0.12 / sqrt(2.0);
  const double pos[4][2] = { { a, -a }, { a, a }, { -a, a }, { -a, -a } }, spin[4] = { -1, 1, -1, 1 };
  for (int i = 0; i < 4; i++) {
    assert_close(p.rotor_pos_m[i][0], pos[i][0], 1e-15);
    assert_close(p.rotor_pos_m[i][1], pos[i][1], 1e-15);
    assert_close(p.rotor_spin[i], spin[i], 0.0);
  }
  /* hover: 4 T_max c^2 = m g -> c = sqrt(0.5 * 9.81 / 12) = sqrt(0.40875) = 0.639335... */
  assert_close(nps_finken_quadrotor_hover_command(&p), 0.6393355, 1e-7);
}

static void rotors_from_a_plus_mixing(void **state)
{
  (void)state;
  /* Paparazzi's QUAD_PLUS: front (CW), right (CCW), back (CW), left (CCW) */
  const double roll[4] = { 0, -256, 0, 256 }, pitch[4] = { 256, 0, -256, 0 }, yaw[4] = { -128, 128, -128, 128 };
  struct nps_finken_quadrotor_params p = finken();
  nps_finken_quadrotor_set_rotors(&p, roll, pitch, yaw, 0.2);
  const double pos[4][2] = { { 0.2, 0 }, { 0, 0.2 }, { -0.2, 0 }, { 0, -0.2 } }, spin[4] = { -1, 1, -1, 1 };
  for (int i = 0; i < 4; i++) {
    assert_close(p.rotor_pos_m[i][0], pos[i][0], 1e-16);
    assert_close(p.rotor_pos_m[i][1], pos[i][1], 1e-16);
    assert_close(p.rotor_spin[i], spin[i], 0.0);
  }
}

static void hover_thrust_holds_the_weight(void **state)
{
  (void)state;
  const struct nps_finken_quadrotor_params p = finken();
  const double c = nps_finken_quadrotor_hover_command(&p), cmd[4] = { c, c, c, c };
  struct nps_finken_quadrotor_state s = flying(0.6, c);
  run(&s, &p, cmd, NULL, 10.0);
  /* forces and torques balance to rounding: nothing moves */
  assert_close(s.pos_m[2], -0.6, 1e-12);
  assert_close(s.pos_m[0], 0.0, 1e-12);
  assert_close(s.vel_mps[2], 0.0, 1e-12);
  assert_close(s.quat[0], 1.0, 1e-15);
  assert_close(s.thrust_n, 0.5 * 9.81, 1e-12);
  assert_false(s.on_ground);
  /* the accelerometer reads the thrust: -g along body z */
  assert_close(s.specific_force_mps2[0], 0.0, 1e-12);
  assert_close(s.specific_force_mps2[2], -9.81, 1e-12);
  assert_close(s.accel_mps2[2], 0.0, 1e-12);
}

static void free_fall_without_drag(void **state)
{
  (void)state;
  struct nps_finken_quadrotor_params p = finken();
  memset(p.drag_ns_m, 0, sizeof(p.drag_ns_m));
  const double off[4] = { 0, 0, 0, 0 };
  struct nps_finken_quadrotor_state s = flying(100.0, 0.0);
  s.vel_mps[0] = 1.0;
  run(&s, &p, off, NULL, 2.0);
  /* z = -100 + g t^2 / 2 = -100 + 19.62 = -80.38; vz = g t = 19.62; x = 2 (Runge-Kutta is exact on polynomials) */
  assert_close(s.pos_m[2], -80.38, 1e-9);
  assert_close(s.vel_mps[2], 19.62, 1e-9);
  assert_close(s.pos_m[0], 2.0, 1e-9);
  assert_close(s.accel_mps2[2], 9.81, 1e-12);
  /* an accelerometer in free fall reads nothing */
  for (int i = 0; i < 3; i++) {
    assert_close(s.specific_force_mps2[i], 0.0, 1e-12);
  }
}

static void free_fall_with_drag(void **state)
{
  (void)state;
  const struct nps_finken_quadrotor_params p = finken();
  const double off[4] = { 0, 0, 0, 0 };
  struct nps_finken_quadrotor_state s = flying(100.0, 0.0);
  run(&s, &p, off, NULL, 2.0);
  /* m dv/dt = m g - D v: v(t) = (m g / D)(1 - exp(-D t / m)), D = 0.2, m = 0.5: 24.525 (1 - e^-0.8) = 13.505209...
   * z(t) = -100 + (m g / D)(t - (m / D)(1 - e^-0.8)) = -100 + 24.525 (2 - 2.5 * 0.550671) = -84.7131...
   * Runge-Kutta error on exp(-0.4 t) at dt = 1/512: ~ (0.4 dt)^5 / 120 per step, far below 1e-9 */
  const double e = 1.0 - exp(-0.8);
  assert_close(s.vel_mps[2], 24.525 * e, 1e-9);
  assert_close(s.pos_m[2], -100.0 + 24.525 * (2.0 - 2.5 * e), 1e-9);
  /* the accelerometer reads the drag: -D v / m along body z */
  assert_close(s.specific_force_mps2[2], -0.2 * s.vel_mps[2] / 0.5, 1e-12);
}

static void differential_speed_yaws(void **state)
{
  (void)state;
  const struct nps_finken_quadrotor_params p = finken();
  /* counter-clockwise rotors (front right, back left) at 0.7, clockwise ones at 0.5:
   * tau_z = k T_max (2 * 0.49 - 2 * 0.25) = 0.01 * 3 * 0.48 = 0.0144 N m; r' = 0.0144 / 2.8e-3 = 5.142857 rad/s^2;
   * the roll and pitch torques cancel (diagonal pairs); after 0.125 s (64 steps): r = 0.6428571, psi = r' t^2 / 2 =
   * 0.0401786 */
  const double cmd[4] = { 0.5, 0.7, 0.5, 0.7 };
  struct nps_finken_quadrotor_state s = flying(100.0, 0.0);
  for (int i = 0; i < 4; i++) {
    s.rotor_speed[i] = cmd[i];
  }
  run(&s, &p, cmd, NULL, 0.125);
  double eulers[3];
  nps_finken_quadrotor_eulers(&s, eulers);
  assert_close(s.rot_accel_rps2[2], 5.142857142857, 1e-12);
  assert_close(s.rates_rps[2], 0.642857142857, 1e-12);
  assert_close(eulers[2], 0.040178571429, 1e-12);
  assert_close(s.rates_rps[0], 0.0, 1e-13);   /* the cancelling torques leave rounding */
  assert_close(s.rates_rps[1], 0.0, 1e-13);
  assert_close(eulers[0], 0.0, 1e-13);
}

static void left_rotor_rolls_right(void **state)
{
  (void)state;
  /* plus layout, arm 0.12 m: left at 0.7 (T = 1.47 N), right at 0.5 (0.75 N), front and back at sqrt(0.37) (1.11 N
   * each: the yaw torques cancel, 2 * 1.11 = 1.47 + 0.75). tau_x = l (1.47 - 0.75) = 0.0864 N m,
   * p' = 0.0864 / 1.5e-3 = 57.6 rad/s^2; after 0.0625 s (32 steps): p = 3.6 rad/s, phi = 57.6 * 0.0625^2 / 2 =
   * 0.1125 rad */
  const double roll[4] = { 0, -256, 0, 256 }, pitch[4] = { 256, 0, -256, 0 }, yaw[4] = { -128, 128, -128, 128 };
  struct nps_finken_quadrotor_params p = finken();
  nps_finken_quadrotor_set_rotors(&p, roll, pitch, yaw, 0.12);
  const double cmd[4] = { sqrt(0.37), 0.5, sqrt(0.37), 0.7 };
  struct nps_finken_quadrotor_state s = flying(100.0, 0.0);
  for (int i = 0; i < 4; i++) {
    s.rotor_speed[i] = cmd[i];
  }
  run(&s, &p, cmd, NULL, 0.0625);
  double eulers[3];
  nps_finken_quadrotor_eulers(&s, eulers);
  assert_close(s.rates_rps[0], 3.6, 1e-12);
  assert_close(eulers[0], 0.1125, 1e-12);
  assert_close(s.rates_rps[1], 0.0, 1e-15);
  assert_close(s.rates_rps[2], 0.0, 1e-13);
  /* right side down: the thrust pulls east (body y, heading 0) */
  assert_true(s.vel_mps[1] > 0.0);
}

static void rotor_speed_lags_the_command(void **state)
{
  (void)state;
  const struct nps_finken_quadrotor_params p = finken();
  const double full[4] = { 1, 1, 1, 1 };
  struct nps_finken_quadrotor_state s = flying(100.0, 0.0);
  /* 30 steps of 1 ms = tau = 0.03 s: the exact lag leaves exp(-1) of the step */
  for (int i = 0; i < 30; i++) {
    nps_finken_quadrotor_step(&s, &p, full, NULL, 0.001);
  }
  assert_close(s.rotor_speed[0], 1.0 - exp(-1.0), 1e-12);
  /* commands are clamped to [0, 1]; NaN counts as 0 */
  const double wild[4] = { 7.0, -3.0, NAN, 1.0 };
  struct nps_finken_quadrotor_params instant = p;
  instant.rotor_tau_s = 0.0;
  nps_finken_quadrotor_step(&s, &instant, wild, NULL, 0.001);
  assert_close(s.rotor_speed[0], 1.0, 0.0);
  assert_close(s.rotor_speed[1], 0.0, 0.0);
  assert_close(s.rotor_speed[2], 0.0, 0.0);
}

static void the_ground_holds_and_releases(void **state)
{
  (void)state;
  const struct nps_finken_quadrotor_params p = finken();
  const double idle[4] = { 0.3, 0.3, 0.3, 0.3 }, climb[4] = { 0.7, 0.7, 0.7, 0.7 };
  struct nps_finken_quadrotor_state s;
  nps_finken_quadrotor_init(&s, 1.0, 2.0, 0.5);
  run(&s, &p, idle, NULL, 1.0);
  assert_true(s.on_ground);
  assert_close(s.pos_m[2], 0.0, 0.0);
  assert_close(s.pos_m[0], 1.0, 0.0);
  assert_close(s.specific_force_mps2[2], -9.81, 1e-12);   /* the ground's push */
  assert_close(s.accel_mps2[2], 0.0, 0.0);
  /* 0.7 > hover 0.639: 4 * 3 * 0.49 = 5.88 N > 4.905 N, it lifts off */
  run(&s, &p, climb, NULL, 1.0);
  assert_false(s.on_ground);
  assert_true(s.pos_m[2] < -0.1);
}

static void a_landing_stops_flat_with_its_heading(void **state)
{
  (void)state;
  const struct nps_finken_quadrotor_params p = finken();
  const double off[4] = { 0, 0, 0, 0 };
  struct nps_finken_quadrotor_state s = flying(0.5, 0.0);
  s.vel_mps[0] = 1.0;
  s.rates_rps[0] = 0.5;
  s.rates_rps[2] = 0.2;
  run(&s, &p, off, NULL, 1.0);
  double eulers[3];
  nps_finken_quadrotor_eulers(&s, eulers);
  assert_true(s.on_ground);
  assert_close(s.pos_m[2], 0.0, 0.0);
  assert_close(s.vel_mps[0], 0.0, 0.0);
  assert_close(eulers[0], 0.0, 1e-15);
  assert_close(eulers[1], 0.0, 1e-15);
  /* it turned at 0.2 rad/s until touch-down, ~0.32 s (0.5 m in free fall with drag), then kept its heading */
  assert_true(eulers[2] > 0.05 && eulers[2] < 0.08);
}

/** Rotational kinetic energy [J] and the angular momentum in the ltp frame [N m s]. */
static double rotation_energy(const struct nps_finken_quadrotor_state *s, const struct nps_finken_quadrotor_params *p,
                              double l_ltp[3])
{
  const double *w = s->rates_rps, *I = p->inertia_kgm2;
  const double l_body[3] = { I[0] * w[0], I[1] * w[1], I[2] * w[2] };
  const struct nps_finken_quadrotor_state conj = { .quat = { s->quat[0], -s->quat[1], -s->quat[2], -s->quat[3] } };
  nps_finken_quadrotor_body_of_ltp(&conj, l_body, l_ltp);
  return 0.5 * (I[0] * w[0] * w[0] + I[1] * w[1] * w[1] + I[2] * w[2] * w[2]);
}

static void energy_and_angular_momentum_are_conserved(void **state)
{
  (void)state;
  /* rotors off, no drag, three different inertias and a tumble about no principal axis (Euler's equations);
   * translation: m v^2 / 2 + m g h; rotation: energy and the ltp angular momentum. Runge-Kutta's error per step
   * ~ (|w| dt)^5 ~ (6 / 512)^5 = 2e-10, over 2560 steps ~ 6e-7 at most: tolerance 1e-6 relative */
  struct nps_finken_quadrotor_params p = finken();
  memset(p.drag_ns_m, 0, sizeof(p.drag_ns_m));
  p.inertia_kgm2[1] = 2.0e-3;
  const double off[4] = { 0, 0, 0, 0 };
  struct nps_finken_quadrotor_state s = flying(1000.0, 0.0);
  s.vel_mps[0] = 1.0;
  s.vel_mps[1] = -2.0;
  s.vel_mps[2] = -0.5;
  s.rates_rps[0] = 3.0;
  s.rates_rps[1] = -2.0;
  s.rates_rps[2] = 5.0;
  const double m = p.mass_kg, g = p.gravity_mps2;
#define TRANSLATION_ENERGY(s) (0.5 * m * ((s).vel_mps[0] * (s).vel_mps[0] + (s).vel_mps[1] * (s).vel_mps[1] + \
                                          (s).vel_mps[2] * (s).vel_mps[2]) - m * g * (s).pos_m[2])
  const double e0 = TRANSLATION_ENERGY(s);
  double l0[3], l1[3];
  const double r0 = rotation_energy(&s, &p, l0);
  run(&s, &p, off, NULL, 5.0);
  const double r1 = rotation_energy(&s, &p, l1);
  assert_close(TRANSLATION_ENERGY(s), e0, 1e-9 * e0);
  assert_close(r1, r0, 1e-6 * r0);
  const double l_norm = sqrt(l0[0] * l0[0] + l0[1] * l0[1] + l0[2] * l0[2]);
  for (int i = 0; i < 3; i++) {
    assert_close(l1[i], l0[i], 1e-6 * l_norm);
  }
  const double *q = s.quat;
  assert_close(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-15);
#undef TRANSLATION_ENERGY
}

static void the_accelerometer_reads_acceleration_minus_gravity(void **state)
{
  (void)state;
  /* tilted, turning, in wind, rotors unequal: specific force = R (a - g) at the end of every step */
  const struct nps_finken_quadrotor_params p = finken();
  const double cmd[4] = { 0.6, 0.7, 0.65, 0.62 }, wind[3] = { 1.0, -0.5, 0.2 };
  struct nps_finken_quadrotor_state s = flying(50.0, 0.6);
  s.quat[0] = cos(0.2);
  s.quat[1] = sin(0.2);   /* phi = 0.4 rad */
  s.vel_mps[0] = 0.7;
  for (int k = 0; k < 100; k++) {
    nps_finken_quadrotor_step(&s, &p, cmd, wind, DT);
    const double a_minus_g[3] = { s.accel_mps2[0], s.accel_mps2[1], s.accel_mps2[2] - p.gravity_mps2 };
    double expect[3];
    nps_finken_quadrotor_body_of_ltp(&s, a_minus_g, expect);
    for (int i = 0; i < 3; i++) {
      assert_close(s.specific_force_mps2[i], expect[i], 1e-12);
    }
  }
}

static void wind_drags_the_copter_along(void **state)
{
  (void)state;
  /* hovering in a 2 m/s north wind: drag D (w - v) / m = 0.13 * 2 / 0.5 = 0.52 m/s^2 northward at first;
   * v_north(t) = 2 (1 - exp(-D t / m)): after 2 s, 2 (1 - e^-0.52) = 0.81097 */
  const struct nps_finken_quadrotor_params p = finken();
  const double c = nps_finken_quadrotor_hover_command(&p), cmd[4] = { c, c, c, c }, wind[3] = { 2.0, 0.0, 0.0 };
  struct nps_finken_quadrotor_state s = flying(10.0, c);
  nps_finken_quadrotor_step(&s, &p, cmd, wind, DT);
  assert_close(s.accel_mps2[0], 0.13 * (2.0 - s.vel_mps[0]) / 0.5, 1e-12);
  run(&s, &p, cmd, wind, 2.0 - DT);
  assert_close(s.vel_mps[0], 2.0 * (1.0 - exp(-0.52)), 1e-9);
  assert_close(s.pos_m[2], -10.0, 1e-12);
}

/*
 * A reference controller (cascade, as Paparazzi's guidance and stabilisation): velocity -> acceleration as the lag
 * model's first-order law a = (v_cmd - v) / tau plus the drag it must overcome (D v / m), height by a PD; acceleration
 * -> roll, pitch and thrust; attitude -> torques by a PD (natural frequency 25 rad/s, damping 0.8, the inertia known);
 * torques and thrust -> rotor thrusts (the X layout inverted) -> commands sqrt(T_i / T_max).
 */
struct controller {
  double tau_s;        ///< velocity time constant [s]
  double height_m;     ///< height held [m]
};

static void control(const struct controller *k, const struct nps_finken_quadrotor_state *s,
                    const struct nps_finken_quadrotor_params *p, const double v_cmd_ne[2], double cmd[4])
{
  const double m = p->mass_kg, g = p->gravity_mps2;
  double eulers[3];
  nps_finken_quadrotor_eulers(s, eulers);
  const double a_n = (v_cmd_ne[0] - s->vel_mps[0]) / k->tau_s + p->drag_ns_m[0] * s->vel_mps[0] / m;
  const double a_e = (v_cmd_ne[1] - s->vel_mps[1]) / k->tau_s + p->drag_ns_m[1] * s->vel_mps[1] / m;
  const double a_up = 16.0 * (k->height_m + s->pos_m[2]) - 8.0 * -s->vel_mps[2];   /* omega 4 rad/s, damping 1 */
  /* heading 0: pitching down (theta < 0) accelerates north, rolling right (phi > 0) east */
  const double theta_d = atan(-a_n / g), phi_d = atan(a_e * cos(theta_d) / g);
  const double thrust = m * (g + a_up) / (cos(eulers[0]) * cos(eulers[1]));
  const double wn = 25.0, zeta = 0.8;
  const double att_err[3] = { phi_d - eulers[0], theta_d - eulers[1], 0.0 - eulers[2] };
  double tau[3];
  for (int i = 0; i < 3; i++) {
    tau[i] = p->inertia_kgm2[i] * (wn * wn * att_err[i] - 2.0 * zeta * wn * s->rates_rps[i]);
  }
  /* X layout, rotors at (+-a, +-a): FL (a, -a, CW), FR (a, a, CCW), BR (-a, a, CW), BL (-a, -a, CCW) */
  const double a = p->rotor_pos_m[0][0], kq = p->torque_coef_m;
  const double t[4] = {
    thrust / 4 + tau[0] / (4 * a) + tau[1] / (4 * a) - tau[2] / (4 * kq),
    thrust / 4 - tau[0] / (4 * a) + tau[1] / (4 * a) + tau[2] / (4 * kq),
    thrust / 4 - tau[0] / (4 * a) - tau[1] / (4 * a) - tau[2] / (4 * kq),
    thrust / 4 + tau[0] / (4 * a) - tau[1] / (4 * a) + tau[2] / (4 * kq),
  };
  for (int i = 0; i < 4; i++) {
    cmd[i] = sqrt(fmin(fmax(t[i] / p->max_thrust_n, 0.0), 1.0));
  }
}

static void closed_loop_follows_a_velocity_step_like_the_lag_model(void **state)
{
  (void)state;
  /*
   * Hovering at 0.6 m, then a 0.5 m/s north step at t = 0 for 4 s. The host's lag model (tau 0.5 s) answers
   * v(t) = 0.5 (1 - exp(-t / 0.5)); the rigid body lags it by its attitude loop and rotor lag (together ~0.07 s, so
   * the largest gap is about 0.5 * 0.07 / 0.5 = 0.07 m/s, early in the step). Tolerances stated: the rigid body's
   * velocity within 0.08 m/s of the lag model's at every step and within 0.005 m/s from t = 2 s on; its 63 % rise
   * time within 0.5-0.62 s (tau plus at most 0.12 s); height within 2 cm of 0.6 m; no lateral drift over 1 mm/s.
   */
  const struct nps_finken_quadrotor_params p = finken();
  const struct controller k = { .tau_s = 0.5, .height_m = 0.6 };
  const double c = nps_finken_quadrotor_hover_command(&p);
  struct nps_finken_quadrotor_state s = flying(0.6, c);
  const struct nps_finken_lag_params lag_p = {
    .velocity_tau_s = 0.5, .yaw_tau_s = 0.3, .altitude_m = 0.6, .altitude_tau_s = 0.5, .max_speed_mps = 1.0,
  };
  struct nps_finken_lag_state lag = { .pos_m = { 0, 0, 0.6 } };
  const double v_cmd[2] = { 0.5, 0.0 };
  double max_gap = 0.0, max_gap_late = 0.0, max_height_err = 0.0, max_east = 0.0, t63 = -1.0;
  for (int i = 1; i <= 4 * 512; i++) {
    const double t = i * DT;
    double cmd[4];
    control(&k, &s, &p, v_cmd, cmd);
    nps_finken_quadrotor_step(&s, &p, cmd, NULL, DT);
    nps_finken_lag_step(&lag, &lag_p, 0.0, 0.5, 0.0, DT);   /* ENU: north is y */
    const double gap = fabs(s.vel_mps[0] - lag.vel_mps[1]);
    max_gap = fmax(max_gap, gap);
    if (t >= 2.0) {
      max_gap_late = fmax(max_gap_late, gap);
    }
    max_height_err = fmax(max_height_err, fabs(-s.pos_m[2] - 0.6));
    max_east = fmax(max_east, fabs(s.vel_mps[1]));
    if (t63 < 0.0 && s.vel_mps[0] >= 0.5 * (1.0 - exp(-1.0))) {
      t63 = t;
    }
  }
  print_message("# rigid body vs lag model: max gap %.4f m/s, after 2 s %.5f m/s, t63 %.4f s, height error %.4f m\n",
                max_gap, max_gap_late, t63, max_height_err);
  assert_true(max_gap <= 0.08);
  assert_true(max_gap_late <= 0.005);
  assert_true(t63 >= 0.5 && t63 <= 0.62);
  assert_true(max_height_err <= 0.02);
  assert_true(max_east <= 1e-3);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(defaults_are_the_finken_estimates),
    cmocka_unit_test(rotors_from_a_plus_mixing),
    cmocka_unit_test(hover_thrust_holds_the_weight),
    cmocka_unit_test(free_fall_without_drag),
    cmocka_unit_test(free_fall_with_drag),
    cmocka_unit_test(differential_speed_yaws),
    cmocka_unit_test(left_rotor_rolls_right),
    cmocka_unit_test(rotor_speed_lags_the_command),
    cmocka_unit_test(the_ground_holds_and_releases),
    cmocka_unit_test(a_landing_stops_flat_with_its_heading),
    cmocka_unit_test(energy_and_angular_momentum_are_conserved),
    cmocka_unit_test(the_accelerometer_reads_acceleration_minus_gravity),
    cmocka_unit_test(wind_drags_the_copter_along),
    cmocka_unit_test(closed_loop_follows_a_velocity_step_like_the_lag_model),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
