//! The attribute lists of `flight_plan.dtd` (2024-10), plus the VFPG extension elements.
//! Upstream validates a plan against its DTD when it declares one: an undeclared attribute, a
//! missing required attribute or a misplaced element is fatal there, and so it is here.
//! Procedures and plans without DOCTYPE are not validated upstream; for them undeclared
//! attributes are kept and reported as warnings.

/// (declared attributes, required attributes) of an element, by lower-case tag.
pub fn attributes(tag: &str) -> Option<(&'static [&'static str], &'static [&'static str])> {
    Some(match tag {
        "flight_plan" => (
            &[
                "name", "lat0", "lon0", "max_dist_from_home", "ground_alt", "security_height", "alt", "wp_frame", "qfu",
                "home_mode_height", "geofence_max_alt", "geofence_max_height", "geofence_sector",
            ],
            &["name", "lat0", "lon0", "max_dist_from_home", "ground_alt", "security_height", "alt"],
        ),
        "procedure" | "header" | "exceptions" | "sectors" | "variables" | "modules" | "blocks" | "includes" | "home"
        | "forbidden_deroutes" => (&[], &[]),
        "waypoints" => (&["utm_x0", "utm_y0"], &[]),
        "waypoint" => (&["name", "x", "y", "lat", "lon", "alt", "height"], &["name"]),
        "sector" => (&["name", "color", "type"], &["name"]),
        "corner" => (&["name"], &["name"]),
        "kml" => (&["file"], &["file"]),
        "variable" => (
            &["var", "type", "init", "shortname", "min", "max", "step", "unit", "alt_unit", "alt_unit_coef", "values"],
            &["var"],
        ),
        "abi_binding" => (&["name", "vars", "id", "handler"], &["name"]),
        "module" => (&["name", "type"], &["name"]),
        "define" => (&["name", "value"], &["name"]),
        "configure" => (&["name", "value"], &["name", "value"]),
        "block" => (
            &[
                "name", "pre_call", "post_call", "on_enter", "on_exit", "strip_button", "strip_icon", "group", "key",
                "description",
            ],
            &["name"],
        ),
        "exception" => (&["cond", "deroute"], &["cond", "deroute"]),
        "while" => (&["cond"], &[]),
        "for" => (&["var", "from", "to"], &["var", "from", "to"]),
        "heading" => (
            &[
                "course", "vmode", "alt", "height", "throttle", "climb", "pitch", "pre_call", "post_call", "nav_type",
                "nav_params", "until", "max_speed",
            ],
            &["course", "until"],
        ),
        "attitude" => (
            &[
                "roll", "vmode", "alt", "height", "throttle", "climb", "pitch", "pre_call", "post_call", "nav_type",
                "nav_params", "until",
            ],
            &["roll"],
        ),
        "go" => (
            &[
                "wp", "wp_qdr", "wp_dist", "from", "from_qdr", "from_dist", "hmode", "vmode", "pitch", "alt", "height",
                "approaching_time", "exceeding_time", "throttle", "climb", "pre_call", "post_call", "nav_type",
                "nav_params", "until", "max_speed",
            ],
            &["wp"],
        ),
        "path" => (
            &[
                "wpts", "vmode", "pitch", "alt", "height", "approaching_time", "exceeding_time", "throttle", "climb",
                "max_speed",
            ],
            &["wpts"],
        ),
        "set" => (&["var", "value"], &["var", "value"]),
        "call" => (&["fun", "until", "loop", "break"], &["fun"]),
        "call_once" => (&["fun", "break"], &["fun"]),
        "follow" => (
            &["ac_id", "distance", "height", "pre_call", "post_call", "nav_type", "nav_params"],
            &["ac_id", "distance", "height"],
        ),
        "xyz" => (&["radius"], &[]),
        "circle" => (
            &[
                "wp", "wp_qdr", "wp_dist", "radius", "alt", "height", "vmode", "climb", "pitch", "throttle", "pre_call",
                "post_call", "nav_type", "nav_params", "until", "max_speed",
            ],
            &["wp", "radius"],
        ),
        "eight" => (
            &[
                "center", "turn_around", "alt", "vmode", "climb", "pitch", "throttle", "pre_call", "post_call", "until",
                "radius", "max_speed",
            ],
            &["center", "turn_around", "radius"],
        ),
        "oval" => (
            &[
                "p1", "p2", "radius", "alt", "vmode", "climb", "pitch", "throttle", "pre_call", "post_call", "until",
                "max_speed",
            ],
            &["p1", "p2", "radius"],
        ),
        "survey_rectangle" => (
            &[
                "grid", "orientation", "wp1", "wp2", "pre_call", "post_call", "nav_type", "nav_params", "until",
                "max_speed",
            ],
            &["grid", "wp1", "wp2"],
        ),
        "stay" => (
            &[
                "wp", "vmode", "throttle", "climb", "alt", "until", "pre_call", "post_call", "nav_type", "nav_params",
                "height", "max_speed",
            ],
            &["wp"],
        ),
        "guided" => (
            &["commands", "flags", "until", "pre_call", "post_call", "nav_type", "nav_params", "max_speed"],
            &["commands"],
        ),
        "deroute" => (&["block"], &["block"]),
        "include" => (&["name", "procedure"], &["name", "procedure"]),
        "arg" => (&["name", "value"], &["name", "value"]),
        "with" => (&["from", "to"], &["from", "to"]),
        "param" => (&["name", "default_value"], &["name"]),
        "return" => (&["reset_stage"], &[]),
        // VFPG extension (not in upstream's DTD).
        "forbidden_deroute" => (&["from", "to", "only_when"], &["from", "to"]),
        _ => return None,
    })
}

/// Attributes that upstream's generator reads although the DTD does not declare them; they are
/// accepted where upstream does not validate (procedures, plans without DOCTYPE).
pub fn undeclared_but_read(tag: &str) -> &'static [&'static str] {
    match tag {
        "exception" => &["exec"],
        "go" => &["x", "y"],
        "stay" => &["hmode", "pitch"],
        "xyz" => &["vmode", "alt", "height", "throttle", "climb", "pitch", "pre_call", "post_call"],
        _ => &[],
    }
}

/// Stage tags allowed in a `<block>`; `while`/`for` allow the same minus `home`.
pub const STAGE_TAGS: &[&str] = &[
    "exception", "while", "heading", "attitude", "go", "xyz", "set", "call", "call_once", "circle", "deroute", "stay",
    "follow", "survey_rectangle", "for", "return", "eight", "oval", "home", "path", "guided",
];

/// Order of the children of `<flight_plan>` in the DTD content model.
pub const PLAN_ORDER: &[&str] = &[
    "header", "waypoints", "sectors", "variables", "modules", "includes", "exceptions", "blocks",
    // VFPG extension, after the blocks.
    "forbidden_deroutes",
];
