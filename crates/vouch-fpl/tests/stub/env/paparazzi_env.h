/*
 * vouch stub: the airframe/module environment that the user C texts of the corpus flight plans
 * name (functions, variables, constants of Paparazzi modules). Written for vouch's tests, not
 * Paparazzi code: it exists so that the *drop-in* header of every corpus plan can be compiled
 * as it is (tests/compile_dropin_corpus.rs). The generator copies these names verbatim; what the
 * test checks is the C the generator composes around them.
 *
 * Module functions are variadic macros that evaluate to a float (their arguments are not
 * evaluated: their types belong to the modules, not to the generator). Names used through
 * `->`, `.` or as lvalues are real objects with the fields the corpus uses.
 */
#ifndef VOUCH_PAPARAZZI_ENV_H
#define VOUCH_PAPARAZZI_ENV_H
#include "std.h"
/* The runtime first, so that the Return override below is the one in force. */
#include "fp_stub.h"

float fp_env_any(void);
float fp_env_call(int unused, ...);
void fp_env_bind(void *ev, void (*cb)(void));

#define FP_ENV_FN fp_env_any()

/* Module functions called without arguments. */
#define DeployParachute() FP_ENV_FN
#define GetAltRef() FP_ENV_FN
#define GetPosAlt() FP_ENV_FN
#define GetPosHeight() FP_ENV_FN
#define GetPosX() FP_ENV_FN
#define GetPosY() FP_ENV_FN
#define GpsFixValid() FP_ENV_FN
#define GpsIsLost() FP_ENV_FN
#define LockParachute() FP_ENV_FN
#define NavCircleCount() FP_ENV_FN
#define NavDetectGround() FP_ENV_FN
#define NavDropCloseHatch() FP_ENV_FN
#define NavDropShoot() FP_ENV_FN
#define NavKillThrottle() FP_ENV_FN
#define NavResurrect() FP_ENV_FN
#define NavSetAltitudeReferenceHere() FP_ENV_FN
#define NavSetGroundReferenceHere() FP_ENV_FN
#define NavStartDetectGround() FP_ENV_FN
#define PowerVoltage() FP_ENV_FN
#define RCLost() FP_ENV_FN
#define RadioControlIsLost() FP_ENV_FN
#define autopilot_in_flight() FP_ENV_FN
#define dc_stop() FP_ENV_FN
#define formation_flight() FP_ENV_FN
#define formation_pre_call() FP_ENV_FN
#define get_sys_time_msec() FP_ENV_FN
#define ground_detect() FP_ENV_FN
#define gvf_nav_survey_polygon_run() FP_ENV_FN
#define ins_reset_altitude_ref() FP_ENV_FN
#define ins_reset_vertical_pos() FP_ENV_FN
#define mission_run() FP_ENV_FN
#define nav_fish_velocity_run() FP_ENV_FN
#define nav_flower_run() FP_ENV_FN
#define nav_is_in_flight() FP_ENV_FN
#define nav_lace_run() FP_ENV_FN
#define nav_launcher_run() FP_ENV_FN
#define nav_launcher_setup() FP_ENV_FN
#define nav_line_setup() FP_ENV_FN
#define nav_rosette_run() FP_ENV_FN
#define nav_set_heading_current() FP_ENV_FN
#define nav_skid_landing_run() FP_ENV_FN
#define nav_survey_hybrid_run() FP_ENV_FN
#define nav_survey_poly_osam_run() FP_ENV_FN
#define nav_survey_poly_run() FP_ENV_FN
#define nav_survey_zamboni_run() FP_ENV_FN
#define nav_takeoff_from_here() FP_ENV_FN
#define nav_trinity_run() FP_ENV_FN
#define reset_nav_reference() FP_ENV_FN
#define reset_waypoints() FP_ENV_FN
#define rotwing_state_hover_motors_running() FP_ENV_FN
#define shift_tracking_reset() FP_ENV_FN
#define start_formation() FP_ENV_FN
#define stateGetHorizontalSpeedNorm_f() FP_ENV_FN
#define stateIsAttitudeValid() FP_ENV_FN
#define stop_formation() FP_ENV_FN
#define tag_tracking_compute_speed() FP_ENV_FN
#define viewvideo_save_shot() FP_ENV_FN

/* Module functions called with arguments: the arguments are evaluated (passed to a variadic
 * sink), so their own names must exist; the result is a float. */
#define And(...) fp_env_call(0, __VA_ARGS__)
#define DOWNLINK_SEND_MARK(...) fp_env_call(0, __VA_ARGS__)
#define GPS_FIX_VALID(...) fp_env_call(0, __VA_ARGS__)
#define LessThan(...) fp_env_call(0, __VA_ARGS__)
#define MoreThan(...) fp_env_call(0, __VA_ARGS__)
#define NavCopyWaypoint(...) fp_env_call(0, __VA_ARGS__)
#define NavCopyWaypointPositionOnly(...) fp_env_call(0, __VA_ARGS__)
#define NavDropComputeApproach(...) fp_env_call(0, __VA_ARGS__)
#define NavDropUpdateRelease(...) fp_env_call(0, __VA_ARGS__)
#define NavGuided(...) fp_env_call(0, __VA_ARGS__)
#define NavQdrCloseTo(...) fp_env_call(0, __VA_ARGS__)
#define NavSetWaypointHere(...) fp_env_call(0, __VA_ARGS__)
#define Or(...) fp_env_call(0, __VA_ARGS__)
#define POS_BFP_OF_REAL(...) fp_env_call(0, __VA_ARGS__)
#define ParachuteComputeApproach(...) fp_env_call(0, __VA_ARGS__)
#define add_slot(...) fp_env_call(0, __VA_ARGS__)
#define approach_moving_target_enable(...) fp_env_call(0, __VA_ARGS__)
#define autopilot_guided_update(...) fp_env_call(0, __VA_ARGS__)
#define autopilot_set_in_flight(...) fp_env_call(0, __VA_ARGS__)
#define autopilot_set_kill_throttle(...) fp_env_call(0, __VA_ARGS__)
#define autopilot_set_mode(...) fp_env_call(0, __VA_ARGS__)
#define autopilot_set_motors_on(...) fp_env_call(0, __VA_ARGS__)
#define autopilot_static_set_mode(...) fp_env_call(0, __VA_ARGS__)
#define calculate_wind_no_airspeed(...) fp_env_call(0, __VA_ARGS__)
#define compute_TOD(...) fp_env_call(0, __VA_ARGS__)
#define compute_alignment(...) fp_env_call(0, __VA_ARGS__)
#define dc_Circle(...) fp_env_call(0, __VA_ARGS__)
#define dc_send_command(...) fp_env_call(0, __VA_ARGS__)
#define follow_me_set_wp(...) fp_env_call(0, __VA_ARGS__)
#define get_dist2_to_waypoint(...) fp_env_call(0, __VA_ARGS__)
#define guidance_h_SetMaxSpeed(...) fp_env_call(0, __VA_ARGS__)
#define gvf_ellipse_XY(...) fp_env_call(0, __VA_ARGS__)
#define gvf_ellipse_wp(...) fp_env_call(0, __VA_ARGS__)
#define gvf_line_wp1_wp2(...) fp_env_call(0, __VA_ARGS__)
#define gvf_line_wp_heading(...) fp_env_call(0, __VA_ARGS__)
#define gvf_nav_survey_polygon_setup(...) fp_env_call(0, __VA_ARGS__)
#define gvf_parametric_2D_bezier_wp(...) fp_env_call(0, __VA_ARGS__)
#define gvf_parametric_2D_trefoil_wp(...) fp_env_call(0, __VA_ARGS__)
#define gvf_parametric_3D_ellipse_wp(...) fp_env_call(0, __VA_ARGS__)
#define gvf_parametric_3D_ellipse_wp_delta(...) fp_env_call(0, __VA_ARGS__)
#define gvf_parametric_3D_lissajous_wp_center(...) fp_env_call(0, __VA_ARGS__)
#define gvf_segment_XY1_XY2(...) fp_env_call(0, __VA_ARGS__)
#define gvf_segment_loop_wp1_wp2(...) fp_env_call(0, __VA_ARGS__)
#define gvf_segment_wp1_wp2(...) fp_env_call(0, __VA_ARGS__)
#define gvf_sin_wp1_wp2(...) fp_env_call(0, __VA_ARGS__)
#define gvf_sin_wp_alpha(...) fp_env_call(0, __VA_ARGS__)
#define hackhd_command(...) fp_env_call(0, __VA_ARGS__)
#define imcu_get_radio(...) fp_env_call(0, __VA_ARGS__)
#define imcu_set_command(...) fp_env_call(0, __VA_ARGS__)
#define jevois_send_string(...) fp_env_call(0, __VA_ARGS__)
#define jevois_stream(...) fp_env_call(0, __VA_ARGS__)
#define nav_compute_baseleg(...) fp_env_call(0, __VA_ARGS__)
#define nav_compute_final_from_glide(...) fp_env_call(0, __VA_ARGS__)
#define nav_cube_run(...) fp_env_call(0, __VA_ARGS__)
#define nav_cube_setup(...) fp_env_call(0, __VA_ARGS__)
#define nav_flower_setup(...) fp_env_call(0, __VA_ARGS__)
#define nav_lace_setup(...) fp_env_call(0, __VA_ARGS__)
#define nav_land_at_loc(...) fp_env_call(0, __VA_ARGS__)
#define nav_land_at_wp(...) fp_env_call(0, __VA_ARGS__)
#define nav_land_here(...) fp_env_call(0, __VA_ARGS__)
#define nav_line_run(...) fp_env_call(0, __VA_ARGS__)
#define nav_rosette_setup(...) fp_env_call(0, __VA_ARGS__)
#define nav_set_heading_deg(...) fp_env_call(0, __VA_ARGS__)
#define nav_set_heading_towards_waypoint(...) fp_env_call(0, __VA_ARGS__)
#define nav_skid_landing_setup(...) fp_env_call(0, __VA_ARGS__)
#define nav_survey_hybrid_setup_towards(...) fp_env_call(0, __VA_ARGS__)
#define nav_survey_poly_osam_setup(...) fp_env_call(0, __VA_ARGS__)
#define nav_survey_poly_setup_towards(...) fp_env_call(0, __VA_ARGS__)
#define nav_survey_rectangle_rotorcraft_run(...) fp_env_call(0, __VA_ARGS__)
#define nav_survey_rectangle_rotorcraft_setup(...) fp_env_call(0, __VA_ARGS__)
#define nav_survey_zamboni_setup(...) fp_env_call(0, __VA_ARGS__)
#define nav_takeoff_from_wp(...) fp_env_call(0, __VA_ARGS__)
#define nav_trinity_setup(...) fp_env_call(0, __VA_ARGS__)
#define power_switch_set(...) fp_env_call(0, __VA_ARGS__)
#define pprzlink_cam_ctrl_set_expo(...) fp_env_call(0, __VA_ARGS__)
#define rotwing_state_choose_circle_direction(...) fp_env_call(0, __VA_ARGS__)
#define rotwing_state_set(...) fp_env_call(0, __VA_ARGS__)
#define set_expo(...) fp_env_call(0, __VA_ARGS__)
#define set_state(...) fp_env_call(0, __VA_ARGS__)
#define shift_tracking_run(...) fp_env_call(0, __VA_ARGS__)
#define tag_tracking_get_heading(...) fp_env_call(0, __VA_ARGS__)
#define tag_tracking_get_status(...) fp_env_call(0, __VA_ARGS__)
#define tag_tracking_set_tracker_id(...) fp_env_call(0, __VA_ARGS__)
#define target_set_wp(...) fp_env_call(0, __VA_ARGS__)
#define waypoint_get_lat_deg(...) fp_env_call(0, __VA_ARGS__)
#define waypoint_get_lon_deg(...) fp_env_call(0, __VA_ARGS__)
#define waypoint_position_copy(...) fp_env_call(0, __VA_ARGS__)
#define waypoint_set_xy_i(...) fp_env_call(0, __VA_ARGS__)

/* Actuator macro of the drop module (plans define it themselves only for SITL). */
#define SwitchServoOff(...) FP_ENV_FN

/* ABI binding functions take the header's event and callback (the callbacks must be used). */
#define AbiBindMsgJEVOIS_MSG(id, ev, cb) fp_env_bind((void *)(ev), (void (*)(void))(cb))
#define AbiBindMsgJOYSTICK(id, ev, cb) fp_env_bind((void *)(ev), (void (*)(void))(cb))
#define AbiBindMsgOBSTACLE_DETECTION(id, ev, cb) fp_env_bind((void *)(ev), (void (*)(void))(cb))
#define AbiBindMsgRANGE_FORCEFIELD(id, ev, cb) fp_env_bind((void *)(ev), (void (*)(void))(cb))
#define ABI_BROADCAST 255
#define UNUSED __attribute__((unused))

/* Accessors returning pointers to state structures. */
struct FloatEulers { float phi, theta, psi; };
struct EnuCoor_f { float x, y, z; };
struct LlaCoor_f { float lat, lon, alt; };
struct FloatVect2 { float x, y; };
struct FloatVect3 { float x, y, z; };
struct FloatQuat { float qi, qx, qy, qz; };
struct fp_env_tag { int status, motion_type; struct FloatVect2 speed_cmd; };
extern struct FloatEulers fp_env_eulers;
extern struct EnuCoor_f fp_env_enu;
extern struct LlaCoor_f fp_env_lla;
extern struct fp_env_tag fp_env_tag;
#define stateGetNedToBodyEulers_f(...) (&fp_env_eulers)
#define stateGetPositionEnu_f(...) (&fp_env_enu)
#define stateGetPositionLla_f(...) (&fp_env_lla)
#define tag_tracking_get(...) (&fp_env_tag)

/* Objects with the fields the corpus reads or assigns. */
extern struct fp_env_autopilot { float flight_time; bool kill_throttle, launch; int mode; } autopilot;
extern struct fp_env_electrical { bool bat_critical, bat_low; float energy; } electrical;
extern struct fp_env_gps { float pacc, pdop, tow; int fix; } gps;
extern struct fp_env_guidance_v { float delta_t, rc_delta_t, th_sp; int mode; } guidance_v;
extern struct fp_env_nav { float climb_vspeed, descend_vspeed, heading, pitch, radius, roll, throttle; } nav;
extern struct fp_env_nav_cube {
  float alpha, grid_x, grid_z; int nline_x, nline_z, nsect_x, nsect_z, sect;
  struct FloatVect3 offset, size;
} nav_cube;
extern struct fp_env_radio_control { int status; float values[8]; } radio_control;
extern struct fp_env_stabilization { float cmd[8]; } stabilization;
extern struct fp_env_state { float h_speed_dir_i; bool ned_initialized_i; } state;
extern struct fp_env_tag_tracking { int status; } tag_tracking;

/* Plain variables of modules and airframe settings. */
extern float agl_dist_value, airborne_wind_dir, baseleg_out_qdr, dist2_to_home, flight_altitude,
  ground_alt, nav_radius, parachute_start_qdr, v_ctl_auto_throttle_cruise_throttle,
  v_ctl_auto_throttle_nominal_cruise_throttle;
extern int agl_dist_valid, datalink_time, dc_autoshoot, demo_module_periodic_10Hz_demo_status,
  demo_module_periodic_1Hz_demo_status, follow_follow_wp_status, force_forward, form_mode,
  gps_mode, h_ctl_disabled, leader_id, lidar_lite_lidar_lite_downlink_status, nav_mode,
  oval_status, px4flow_i2c_px4flow_i2c_downlink_status, rectangle_survey_sweep_num, sweep,
  tag_tracking_tag_tracking_report_status, unit;
extern float agl_dist_value_filtered, autopilot_flight_time, fp_pitch, nav_climb, nav_flight_altitude;
extern int autopilot_mode_auto2, autopilot_motors_on;

/* Constants of modules and airframes. */
#define AP_MODE_AUTO2 1
#define AP_MODE_GUIDED 2
#define AP_MODE_NAV 3
#define COMMAND_FLAPS 1
#define COMMAND_THRUST_X 2
#define DC_AUTOSHOOT_DISTANCE 1
#define DC_AUTOSHOOT_STOP 0
#define DC_OFF 0
#define DEFAULT_CIRCLE_RADIUS 50.f
#define DefaultChannel 0
#define DefaultDevice 0
#define FLARE_HEIGHT 10.f
#define GUIDED_FLAG_XY_OFFSET 1
#define GUIDED_FLAG_XY_VEL 2
#define GUIDED_FLAG_Z_VEL 4
#define HYBRID_HEIGHT 20.f
#define LIFTOFF_PITCH_LIMIT_DEG 5.f
#define LIFTOFF_ROLL_LIMIT_DEG 5.f
#define MAX_PPRZ 9600
#define MIN_PPRZ (-9600)
#define MINIMUM_AIRSPEED 10.f
#define MODULES_START 1
#define MODULES_STOP 2
#define NAV_MODE_ROLL 1
#define OC1 1
#define PPRZLINK_CAM_AUTO_EXPO 1
#define PolySurveySweepBackNum 1
#define RADIO_THROTTLE 0
#define RADIO_YAW 1
#define RC_REALLY_LOST 2
#define ROTWING_STATE_FORCE_HOVER 1
#define ROTWING_STATE_FREE 2
#define ROTWING_STATE_REQUEST_FW 3
#define ROTWING_STATE_REQUEST_HOVER 4
#define TAG_TRACKING_ANY 0
#define TAG_TRACKING_DISABLE 1
#define TAG_TRACKING_FIXED_POS 2
#define TAG_TRACKING_LOST 3
#define TAG_TRACKING_MOVING 4
#define TAG_TRACKING_RUNNING 5
#define TAG_TRACKING_SEARCHING 6
#define TRANSITION_HEIGHT 20.f
#define V_CTL_AUTO_THROTTLE_MIN_CRUISE_THROTTLE 0.3f
#define AP_MODE_ATTITUDE_DIRECT 4
#define GLIDE_AIRSPEED 12.f
#define GUIDED_FLAG_XY_BODY 8
#define JEVOIS_MSG_D3 3
#define PolySurveySweepNum 1
#define TAG_TRACKING_COORD_TO_M 0.001f
#define DegOfRad(x) ((x) * (180. / 3.14159265358979323846))

/* Guidance-vector-field parameter structures. */
extern struct fp_env_gvf_ellipse_par { float a, alpha, b; } gvf_ellipse_par;
extern struct fp_env_gvf_line_par { float heading; } gvf_line_par;
extern struct fp_env_gvf_trefoil_par { float alpha, r, ratio, w1, w2; } gvf_parametric_2d_trefoil_par;
extern struct fp_env_gvf_ellipse3d_par { float alpha, r, zh, zl; } gvf_parametric_3d_ellipse_par;
extern struct fp_env_gvf_lissajous_par { float alpha, cx, cy, cz, dx, dy, dz, wx, wy, wz; } gvf_parametric_3d_lissajous_par;
extern struct fp_env_gvf_segment_par { float d1, d2; } gvf_segment_par;
extern struct fp_env_gvf_sin_par { float A, alpha, off, w; } gvf_sin_par;

/* One corpus plan (tcas.xml) calls `Return()` from its own C text: an empty argument means 0. */
#undef Return
#define Return(...) nav_return((uint8_t)(__VA_ARGS__ + 0))

/* Further module functions (same two shapes as above). */
#define AirbrakesOff() FP_ENV_FN
#define AirbrakesOn() FP_ENV_FN
#define CloseRadAngles(...) fp_env_call(0, __VA_ARGS__)
#define DistanceSquare(...) fp_env_call(0, __VA_ARGS__)
#define DownlinkSendWpNr(...) fp_env_call(0, __VA_ARGS__)
#define Fly() FP_ENV_FN
#define ForceCrash() FP_ENV_FN
#define NavSetWaypointPosAndAltHere(...) fp_env_call(0, __VA_ARGS__)
#define RadioControlValues(...) fp_env_call(0, __VA_ARGS__)
#define ThrottleHigh() FP_ENV_FN
#define autopilot_get_mode() FP_ENV_FN
#define gps_has_been_good() FP_ENV_FN
#define increase_nav_heading(...) fp_env_call(0, __VA_ARGS__)
#define nav_bungee_takeoff_run() FP_ENV_FN
#define nav_bungee_takeoff_setup(...) fp_env_call(0, __VA_ARGS__)
#define nav_drop_compute_approach(...) fp_env_call(0, __VA_ARGS__)
#define nav_drop_update_release(...) fp_env_call(0, __VA_ARGS__)
#define nav_line_border_run(...) fp_env_call(0, __VA_ARGS__)
#define nav_line_border_setup() FP_ENV_FN
#define nav_line_osam_block_run(...) fp_env_call(0, __VA_ARGS__)
#define nav_spiral_run() FP_ENV_FN
#define nav_spiral_setup(...) fp_env_call(0, __VA_ARGS__)
#define nav_survey_poly_osam_setup_towards(...) fp_env_call(0, __VA_ARGS__)
#define nav_survey_polygon_run() FP_ENV_FN
#define nav_survey_polygon_setup(...) fp_env_call(0, __VA_ARGS__)
#define nav_vertical_raster_run(...) fp_env_call(0, __VA_ARGS__)
#define nav_vertical_raster_setup() FP_ENV_FN
#define rotwing_request_configuration(...) fp_env_call(0, __VA_ARGS__)
#define rotwing_state_force_skew_off() FP_ENV_FN
#define snav_circle1() FP_ENV_FN
#define snav_circle2() FP_ENV_FN
#define snav_init(...) fp_env_call(0, __VA_ARGS__)
#define snav_on_time(...) fp_env_call(0, __VA_ARGS__)
#define snav_route() FP_ENV_FN

/* Further airframe constants (any value: only their use in the plans' C is compiled) and
 * module variables. */
#define CLIMB_AIRSPEED 1
#define COMMAND_MOTOR_PUSHER 1
#define GLIDE_PITCH 1
#define GLIDE_VSPEED 1
#define GUIDED_FLAG_YAW_OFFSET 1
#define GUIDED_FLAG_YAW_RATE 1
#define HACKHD_POWER_OFF 1
#define HACKHD_POWER_ON 1
#define HACKHD_SHOOT 1
#define HORIZONTAL_MODE_ATTITUDE 1
extern float ImageCapture_image_capture_run_status;
#define LANDING_CIRCLE_RADIUS 1
#define LOW_BAT_LEVEL 1
#define MIN_CIRCLE_RADIUS 1
#define M_PI 3.14159265358979323846
#define M_PI_2 1.57079632679489661923
#define NAVIGATION_FREQUENCY 1
#define NOMINAL_AIRSPEED 1
#define POLYSURVEY_DEFAULT_DISTANCE 1
#define RACE_AIRSPEED 1
#define ROTWING_CONFIGURATION_EFFICIENT 1
#define ROTWING_CONFIGURATION_HOVER 1
#define ROTWING_CONFIGURATION_HYBRID 1
#define STABILIZATION_ATTITUDE_SP_MAX_PHI 1
#define STABILIZATION_ATTITUDE_SP_MAX_THETA 1
#define VERTICAL_MODE_MANUAL 1
#define V_CTL_ALTITUDE_MAX_CLIMB 1
#define V_CTL_AUTO_THROTTLE_MAX_CRUISE_THROTTLE 1
#define V_CTL_AUTO_THROTTLE_NOMINAL_CRUISE_THROTTLE 1
#define V_CTL_GLIDE_RATIO 1
#define V_CTL_SPEED_AIRSPEED 1
extern struct fp_env_air_data { float calc_qnh_once; } air_data;
extern float baro_MS5534A_ground_pressure;
extern float baro_MS5534A_pressure;
extern float commands[8];
extern float dw1000_use_ekf;
extern float hackhd_hackhd_autoshoot_status;
extern float horizontal_mode;
extern float launch;
extern float nav_airspeed_landing_setting;
extern float nav_airspeed_nominal_setting;
extern float nav_airspeed_tracking_setting;
extern float nav_course;
extern float nav_drop_start_qdr;
extern float nav_drop_trigger_delay;
extern float nav_oval_count;
extern float nav_shift;
extern float nav_takeoff_pitch_setting;
extern float obstacle_detected;
extern struct fp_env_rotwing_state { float force_skew, sp_skew_angle_deg; } rotwing_state;
extern float snav_desired_tow;
extern float target_localization_update_wp;
extern float v_ctl_auto_airspeed_setpoint;
extern float v_ctl_auto_throttle_nominal_cruise_pitch;
extern float v_ctl_speed_mode;
extern float vertical_mode;
#define AUTO1_MAX_PITCH 1
#define AUTO1_MAX_ROLL 1
#define LATERAL_MODE_ROLL 1
#define V_CTL_MODE_MANUAL 1
extern float h_ctl_pitch_setpoint;
extern float h_ctl_roll_setpoint;
extern float lateral_mode;
extern float v_ctl_mode;
extern float v_ctl_throttle_setpoint;
#define nav_set_heading_rad(...) fp_env_call(0, __VA_ARGS__)
#define RC_OK 1
extern float force_forward_flight;
extern struct fp_env_sonar_adc { float distance; } sonar_adc;
extern float take_heading_control;
#endif
