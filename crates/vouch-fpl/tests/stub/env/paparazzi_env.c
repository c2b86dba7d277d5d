/* vouch stub: definitions of the environment objects declared in paparazzi_env.h. */
#include "paparazzi_env.h"

float fp_env_any(void) { return 0.f; }
float fp_env_call(int unused, ...) { (void)unused; return 0.f; }
void fp_env_bind(void *ev, void (*cb)(void)) { (void)ev; (void)cb; }

struct FloatEulers fp_env_eulers;
struct EnuCoor_f fp_env_enu;
struct LlaCoor_f fp_env_lla;
struct fp_env_tag fp_env_tag;
struct fp_env_autopilot autopilot;
struct fp_env_electrical electrical;
struct fp_env_gps gps;
struct fp_env_guidance_v guidance_v;
struct fp_env_nav nav;
struct fp_env_nav_cube nav_cube;
struct fp_env_radio_control radio_control;
struct fp_env_stabilization stabilization;
struct fp_env_state state;
struct fp_env_tag_tracking tag_tracking;
float agl_dist_value, airborne_wind_dir, baseleg_out_qdr, dist2_to_home, flight_altitude,
  ground_alt, nav_radius, parachute_start_qdr, v_ctl_auto_throttle_cruise_throttle,
  v_ctl_auto_throttle_nominal_cruise_throttle;
int agl_dist_valid, datalink_time, dc_autoshoot, demo_module_periodic_10Hz_demo_status,
  demo_module_periodic_1Hz_demo_status, follow_follow_wp_status, force_forward, form_mode,
  gps_mode, h_ctl_disabled, leader_id, lidar_lite_lidar_lite_downlink_status, nav_mode,
  oval_status, px4flow_i2c_px4flow_i2c_downlink_status, rectangle_survey_sweep_num, sweep,
  tag_tracking_tag_tracking_report_status, unit;
float agl_dist_value_filtered, autopilot_flight_time, fp_pitch, nav_climb, nav_flight_altitude;
int autopilot_mode_auto2, autopilot_motors_on;
struct fp_env_gvf_ellipse_par gvf_ellipse_par;
struct fp_env_gvf_line_par gvf_line_par;
struct fp_env_gvf_trefoil_par gvf_parametric_2d_trefoil_par;
struct fp_env_gvf_ellipse3d_par gvf_parametric_3d_ellipse_par;
struct fp_env_gvf_lissajous_par gvf_parametric_3d_lissajous_par;
struct fp_env_gvf_segment_par gvf_segment_par;
struct fp_env_gvf_sin_par gvf_sin_par;
float ImageCapture_image_capture_run_status;
struct fp_env_air_data air_data;
float baro_MS5534A_ground_pressure;
float baro_MS5534A_pressure;
float commands[8];
float dw1000_use_ekf;
float hackhd_hackhd_autoshoot_status;
float horizontal_mode;
float launch;
float nav_airspeed_landing_setting;
float nav_airspeed_nominal_setting;
float nav_airspeed_tracking_setting;
float nav_course;
float nav_drop_start_qdr;
float nav_drop_trigger_delay;
float nav_oval_count;
float nav_shift;
float nav_takeoff_pitch_setting;
float obstacle_detected;
struct fp_env_rotwing_state rotwing_state;
float snav_desired_tow;
float target_localization_update_wp;
float v_ctl_auto_airspeed_setpoint;
float v_ctl_auto_throttle_nominal_cruise_pitch;
float v_ctl_speed_mode;
float vertical_mode;
float h_ctl_pitch_setpoint;
float h_ctl_roll_setpoint;
float lateral_mode;
float v_ctl_mode;
float v_ctl_throttle_setpoint;
float force_forward_flight;
struct fp_env_sonar_adc sonar_adc;
float take_heading_control;
