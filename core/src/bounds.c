/* The plausibility bounds table (rb_bounds.h) and the checks built on it. */
#include "railbrake/rb_bounds.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* The physical ranges are wide margins around typical values [T]: high-speed EMU cars of 40 to
 * 70 t, reservoirs of 50 to 400 l, cylinders of 0.5 to 5 l (EP-brake bogie units); the numerical
 * limits are derived in rb_bounds.h. */
static const rb_bound bounds[] = {
    {"car.mass", "kg", 5e3, 2e5, "a car of 5 to 200 t; lighter makes the couplers too stiff for dt"},
    {"coupler.stiffness", "N/m", 1e4, 1e9, "stable mechanics: dt sqrt(4 k / m) < 2 at 5 t"},
    {"coupler.damping", "N.s/m", 0.0, 2e6, "stable mechanics: dt 4 c / m < 2 at 5 t"},
    {"main_reservoir_volume", "m3", 0.01, 10.0, "10 l to 10 m3 of main reservoir"},
    {"car.supply_volume", "m3", 5e-3, 1.0, "5 to 1000 l of supply reservoir per car (typically 50 to 150 l)"},
    {"car.cylinder_volume", "m3", 1e-5, 0.1, "10 cm3 to 100 l per axle; smaller: R T / V unbounded"},
    {"car.pipe_volume", "m3", 1e-6, 5.0, "a finite pressure per kg of air"},
    {"car.pilot_volume", "m3", 1e-5, 0.01, "10 cm3 to 10 l of EP pilot chamber (and a finite pressure per kg of air)"},
    {"car.relay_volume", "m3", 1e-5, 0.02, "10 cm3 to 20 l of relay output chamber and piping"},
    {"car.cylinder_area", "m2", 2e-3, 0.1, "a brake-cylinder piston of 50 to 357 mm diameter"},
    {"car.hold_area", "m2", 1e-7, 1e-3, "a valve port of 0.1 mm2 to 36 mm diameter"},
    {"car.vent_area", "m2", 1e-7, 1e-3, "a valve port of 0.1 mm2 to 36 mm diameter"},
    {"car.valve_delay", "s", 0.0, 0.2, "a WSP solenoid valve switching within 200 ms (10-30 ms, EN 15595)"},
    {"car.ep_tau", "s", 1e-3, 2.0, "an EP valve lag of 1 ms to 2 s"},
    {"car.ep_supply_margin", "Pa", 0.0, 2e5, "an EP valve output held 0 to 2 bar below its supply"},
    {"car.ep_bleed_area", "m2", 0.0, 3e-6, "an EP pilot feed orifice of 0 to 2 mm diameter (typically 0.2 to 0.5 mm)"},
    {"car.relay_tau", "s", 0.0, 0.1, "a relay membrane responding within 100 ms"},
    {"car.relay_sweep", "m3", 0.0, 2e-4, "a relay membrane sweeping 0 to 200 cm3 (and less than the pilot volume)"},
    {"car.relay_travel", "1", 1.0, 10.0, "a membrane travel of 1 to 10 times its full-opening stroke"},
    {"car.supply_pressure", "Pa", 1.2e5, 1.1e6, "0.2 to 11 bar absolute: the ideal-gas air of the model holds below 10 bar gauge"},
    {"compressor_flow", "kg/s", 0.0, 1.0, "up to 50 m3/min of free air"},
    /* Absolute pressures of the main reservoir; from the highest atmosphere (train.atmosphere) up, so
     * that rb_plant_check's "not below the atmosphere" holds over the whole range. */
    {"initial_pressure", "Pa", 1.2e5, 2e6, "main reservoir charged to 1.2 to 20 bar absolute"},
    {"governor_on", "Pa", 1.2e5, 2e6, "a compressor starting below 1.2 to 20 bar absolute"},
    {"governor_off", "Pa", 1.2e5, 2e6, "a compressor stopping above 1.2 to 20 bar absolute (and governor_on)"},
    {"condition.mu0", "1", 1e-6, 2.0, "a Polach maximum friction coefficient (dry rail about 0.55)"},
    {"initial_speed", "m/s", 0.0, 150.0, "up to 540 km/h"},
    {"temperature", "K", 200.0, 400.0, "-73 to 127 degC"},
    {"wall_time", "s", 0.0, 1e3, "a wall heat-exchange time of the cylinders' air up to 1000 s (0: isothermal)"},
    {"bcu.cycle", "s", 1e-4, 0.1, "a BCU cycle of 0.1 to 100 ms"},
    {"bcu.service_decel", "m/s2", 0.0, 3.0, "up to 3 m/s2"},
    {"bcu.emergency_decel", "m/s2", 0.0, 3.0, "up to 3 m/s2"},
    {"bcu.service_jerk", "m/s3", 0.0, 20.0, "a service jerk limit up to 20 m/s3 (0: none)"},
    {"wsp.ref_decel_max", "m/s2", 0.1, 10.0, "a reference speed that can follow a braking train"},
    {"wsp.ref_accel_max", "m/s2", 0.0, 10.0, "a bounded rise of the reference speed"},
    {"wsp.speed_threshold", "m/s", 0.01, 10.0, "a slide of 0.04 to 36 km/h starts venting"},
    {"wsp.slip_threshold", "1", 0.0, 0.5, "up to 50 % of the reference speed"},
    {"wsp.decel_threshold", "m/s2", 0.1, 100.0, "a positive wheel deceleration"},
    {"wsp.reaccel_threshold", "m/s2", 0.0, 100.0, "a non-negative wheel acceleration"},
    {"wsp.release_fraction", "1", 0.0, 1.0, "a fraction of the threshold"},
    {"wsp.reapply_on", "s", 1e-3, 1.0, "hold-valve pulses of 1 ms to 1 s"},
    {"wsp.reapply_off", "s", 1e-3, 1.0, "hold-valve pulses of 1 ms to 1 s"},
    {"wsp.reapply_time", "s", 0.0, 30.0, "full re-application within 30 s"},
    {"wsp.filter_time", "s", 1e-3, 1.0, "a filter of 1 ms to 1 s"},
    {"wsp.safety_time", "s", 0.5, 30.0, "0.5 to 30 s of continuous venting (typically 5-10 s [T]); 0 isolates every axle"},
    {"wsp.min_speed", "m/s", 0.0, 10.0, "WSP active down to at most 36 km/h"},
    {"wsp.controller", "1", 0.0, 2.0, "0: threshold state machine, 1: slip set-point, 2: deceleration and slip speed"},
    {"wsp.setpoint_speed", "m/s", 0.01, 10.0, "a slip-velocity set-point of 0.04 to 36 km/h"},
    {"wsp.setpoint_slip", "1", 0.0, 0.5, "up to 50 % of the reference speed"},
    {"wsp.setpoint_band", "1", 0.0, 0.9, "a hold band of up to +-90 % of the set-point"},
    {"wsp.lead_time", "s", 0.0, 1.0, "the slip predicted up to 1 s ahead"},
    {"wsp.ref_decel_margin", "m/s2", 0.0, 5.0, "a speed estimate falling up to 5 m/s2 faster than the body"},
    {"wsp.setpoint_release", "s", 0.0, 600.0, "an axle let go after up to 10 min braked as demanded"},
    {"wsp.setpoint_memory", "1", 0.1, 1.0, "re-applied quickly to 10 to 100 % of the pressure that slid"},
    {"wsp.setpoint_ramp", "Pa/s", 0.0, 1e6, "a ceiling rising at up to 10 bar/s"},
    {"wsp.ds_speed_threshold", "m/s", 0.01, 10.0, "a slip speed of 0.04 to 36 km/h vents"},
    {"wsp.ds_slip_threshold", "1", 0.0, 0.5, "up to 50 % of the reference speed"},
    {"wsp.ds_decel_threshold", "m/s2", 0.1, 100.0, "a positive wheel deceleration"},
    {"wsp.ds_reaccel_threshold", "m/s2", 0.0, 100.0, "a non-negative wheel re-acceleration"},
    {"wsp.conditioning_mode", "1", 0.0, 1.0, "1: the trailing axle of each bogie slides more"},
    {"wsp.conditioning_ratio", "1", 1.0, 20.0, "the trailing axle's slip criterion 1 to 20 times the leading one's"},

    /* The files' quantities (train, scenario, valve files) that the plant gets only through others:
     * checked by the Python schemas (railbrake._core.bound) in the file's unit, so that a value is
     * refused with its file, line and key before any C struct is built. [T] unless marked. */
    {"train.max_speed", "m/s", 50.0 / 3.6, 500.0 / 3.6, "a high-speed train of 50 to 500 km/h"},
    {"train.atmosphere", "Pa", 5e4, 1.2e5, "sea level to about 5500 m altitude"},
    {"train.car_tare", "kg", 5e3, 1e5, "an empty car of 5 to 100 t (high-speed EMU cars 40 to 55 t)"},
    {"train.car_payload", "kg", 0.0, 6e4, "up to 60 t of load per car (crush load of EMUs about 9 t)"},
    {"train.car_length", "m", 5.0, 40.0, "a car of 5 to 40 m over couplers (EMU cars 25 to 27 m)"},
    {"train.wheel_radius", "m", 0.3, 0.65, "wheels of 600 to 1300 mm diameter (high-speed: 860 to 920 mm new)"},
    {"train.wheelset_inertia", "kg.m2", 10.0, 1000.0, "a wheelset with discs (and a reflected rotor) of 10 to 1000 kg m2"},
    {"train.disc_radius", "m", 0.1, 0.5, "a friction radius inside the wheel (radius at most 0.65 m)"},
    {"train.disc_mass", "kg", 10.0, 500.0, "one disc of 10 to 500 kg"},
    {"train.disc_specific_heat", "J/(kg.K)", 300.0, 1000.0, "steel 460, cast iron 500, aluminium 900 J/(kg K)"},
    {"train.disc_cooling", "W/K", 0.0, 1e4, "convective cooling of one disc up to 10 kW/K"},
    {"train.disc_surface_share", "1", 0.01, 0.9, "a friction surface layer of 1 to 90 % of the disc's heat capacity"},
    {"train.disc_surface_conductance", "W/K", 1.0, 1e5, "a surface layer linked to the disc's bulk by 1 W/K to 100 kW/K"},
    {"train.pad_fade_onset", "K", 273.15, 1273.15, "pads that begin to fade at a friction surface of 0 to 1000 degC"},
    {"train.pad_fade_rate", "1/K", 0.0, 0.01, "a fading of up to 1 % of the friction per kelvin above the onset"},
    {"train.sand_rate", "kg/s", 0.0, 1.0, "a sander's sand (both rails) up to 60 kg/min"},
    {"train.cylinder_stroke", "m", 1e-3, 0.1, "a piston stroke of 1 to 100 mm"},
    {"train.cylinder_dead_volume", "m3", 0.0, 0.02, "up to 20 l of cylinder dead volume and piping"},
    {"train.return_spring", "N", 0.0, 2e4, "a return spring of up to 20 kN"},
    {"train.lever_ratio", "1", 0.5, 10.0, "caliper lever ratios of 0.5 to 10"},
    {"train.caliper_efficiency", "1", 0.5, 1.0, "EN 14531-1: caliper efficiency above 90 % [P]; margin to 50 %"},
    {"train.pad_friction", "1", 0.1, 0.6, "organic and sintered pads: lambda of 0.25 to 0.45 (UIC 541-3) with margin"},
    {"train.pad_sintered_low_speed", "1", 0.35, 0.6, "the default sintered curve falls to 0.35 at 100 km/h: at standstill at least that"},
    {"train.charge_area", "m2", 1e-7, 2e-4, "a check valve and choke of 0.1 to 200 mm2"},
    {"train.valve_port_area", "m2", 1e-7, 5e-4, "a valve port of 0.1 to 500 mm2 (up to 25 mm diameter)"},
    {"train.valve_band", "Pa", 100.0, 2e5, "a pressure-control dead band of 1 mbar to 2 bar"},
    {"train.ed_response", "s", 1e-3, 5.0, "an ED brake that responds within 5 s"},
    {"train.ed_scale", "1", 0.0, 10.0, "a scale of the published ED curve of 0 to 10"},
    {"train.ed_fade_speed", "m/s", 0.0, 50.0 / 3.6, "the ED brake fades out below at most 50 km/h"},
    {"train.ed_force", "N", -1e3, 2e6, "an ED force of the whole train up to 2 MN (CRH380AL: about 0.5 MN)"},
    {"train.ed_c0", "N", -1e7, 1e7, "a constant term of an ED branch within 10 MN"},
    {"train.ed_c1", "N.s/m", -7e4, 7e4, "a linear term of an ED branch within 10 MN at 540 km/h"},
    {"train.ed_c2", "W", -1e8, 1e8, "a power term of an ED branch within 100 MW (CRH380AL about 43 MW)"},
    {"train.table_speed", "m/s", 0.0, 150.0, "speeds of a table within the model's 0 to 540 km/h"},
    {"train.resistance_a", "N", 0.0, 5e4, "the constant running resistance of a train up to 50 kN"},
    {"train.resistance_b", "N.s/m", 0.0, 3600.0, "up to 1 kN per km/h"},
    {"train.resistance_c", "N.s2/m2", 0.0, 648.0, "up to 0.05 kN per (km/h)^2 (aerodynamic drag)"},
    {"train.compressor_delivery", "kg/s", 1e-4, 0.2, "a compressor of 5 l/min to 10 m3/min of free air"},
    {"train.pipe_diameter", "m", 0.01, 0.05, "a main reservoir pipe of 10 to 50 mm (typically 25 mm)"},
    {"train.air_flow_area", "m2", 1e-6, 2e-3, "a flow area of 1 to 2000 mm2 (a 50 mm pipe)"},
    {"train.main_reservoir_min_working", "Pa", 1e5, 1e6, "a minimum working pressure of 1 to 10 bar gauge"},
    {"train.main_reservoir_gauge", "Pa", 4e5, 1e6, "main reservoir of 4 to 10 bar gauge: the ideal-gas air of the model holds below 10 bar (docs/pneumatics.md)"},
    {"train.discharge_coefficient", "1", 0.3, 1.0, "a discharge coefficient of real ports (sharp-edged about 0.6-0.8)"},
    {"train.critical_ratio", "1", 0.1, 0.9, "ISO 6358 critical pressure ratio b of real valves (ideal nozzle 0.528)"},
    {"train.coupler_slack", "m", 0.0, 0.1, "coupler slack of up to 100 mm"},
    {"train.emergency_drop_out", "s", 0.0, 2.0, "an emergency loop's relays dropping out within 2 s (TSI: delay time ta <= 2 s)"},
    {"train.emergency_propagation", "m/s", 50.0, 3e8, "an emergency command travelling 50 m/s (brake pipe: >= 250 m/s) up to the speed of light"},
    {"train.emergency_valve_response", "s", 0.0, 1.0, "an emergency solenoid valve acting within 1 s (10 to 30 ms typical)"},
    {"train.emergency_choke", "m", 1e-4, 1.1e-2, "an emergency choke (nozzle) of 0.1 to 11 mm diameter"},
    {"train.emergency_limit", "Pa", 0.5e5, 9e5, "a load-weighing valve's limit of 0.5 to 9 bar gauge"},
    {"scenario.stop_speed", "m/s", 0.0, 10.0, "the run ends below this speed: a stop is under 36 km/h"},
    {"scenario.max_time", "s", 1.0, 3600.0, "a brake application of 1 s to 1 h"},
    {"scenario.event_time", "s", 0.0, 3600.0, "a demand step or fault within the longest run (1 h)"},
    {"scenario.record_interval", "s", 1e-3, 1.0, "no finer than the plant's 1 ms step, at least one sample a second"},
    {"scenario.recorded_values", "1", 1.0, 1.25e8, "samples x channels of one recording: at most 1 GB of doubles in memory"},
    {"scenario.track_position", "m", -1e3, 1e5, "0 m is the train's front at the start; 100 km covers a stop from 540 km/h at 0.12 m/s2"},
    {"scenario.gradient", "1", -0.1, 0.1, "within +-100 permille (the steepest high-speed lines: 40 permille)"},
    {"scenario.fault_leak_area", "m2", 1e-8, 1e-3, "a leak of 0.01 mm2 up to a 36 mm port"},
    {"scenario.fault_noise", "m/s", 0.0, 10.0, "speed-sensor noise of up to 36 km/h rms"},
    {"scenario.fault_pressure", "Pa", 0.0, 10e5, "a failed relay valve or limiter held at 0 (no output) to 10 bar gauge: the model's ideal gas holds below 10 bar"},
    {"adhesion.creep", "1", -1.0, 1.0, "creep = slip velocity / speed: 1 is a locked wheel (a fraction, not percent)"},
    {"adhesion.coefficient", "1", -1.0, 1.0, "F/Q of wheel on rail: dry rail reaches about 0.5"},
    {"adhesion.target_peak", "1", 0.005, 1.0, "a peak adhesion a train can brake on (EN 15595 extremely low: 0.02 to 0.05)"},
    {"adhesion.target_tolerance", "1", 1e-3, 1.0, "a calibration target met within 0.1 % to 100 %"},
    {"adhesion.recovery_axles", "1", 0.1, 100.0, "the rail recovers behind 0.1 to 100 axles (a train has at most 64)"},
    {"adhesion.reference_energy", "J/m2", 1.0, 1e9, "contact energy per rail area that cleans 63 % of the contamination: 1 J/m2 to 1 GJ/m2"},
    {"adhesion.v_ref", "m/s", 1.0, 1e4, "a rolling speed of 3.6 to 36000 km/h at which wet rail's mu0 is halved (none: no rolling-speed factor)"},
    {"adhesion.rail_cell_length", "m", 0.01, 10.0, "rail cells of 1 cm to 10 m (axles of a bogie stand 2.5 m apart)"},
    {"profile.response_time", "s", 0.0, 30.0, "a brake delay or build-up of up to 30 s (EMUs: ta + tb/2 of 1 to 4 s, EN 14531-1)"},
    {"profile.deceleration", "m/s2", 0.01, 5.0, "a demanded deceleration of 0.01 to 5 m/s2 (beyond, no wheel-rail adhesion)"},
    /* Study files' assessment and tuning limits (railbrake.campaign.study). */
    {"study.delta_s", "1", 0.0, 10.0, "a stopping distance up to 11 times the dry reference's (dS up to 1000 %)"},
    {"study.air_drawn", "kg", 0.0, 1e3, "air drawn in one stop up to 1 t (an EMU's main reservoirs hold a few kg)"},
    {"valve.supply_gauge", "Pa", 1e5, 1e6, "1 to 10 bar gauge: the ideal-gas air of the model holds below 10 bar (docs/pneumatics.md)"},
    /* The valve design files (src/railbrake/data/valves: EP valve, relay valve, solenoid), checked
     * by railbrake.valves.params key by key in the file's unit; wide margins around the small
     * pneumatic and solenoid valves of brake control units [T]. */
    {"valve.moving_mass", "kg", 1e-4, 50.0, "a moving part of 0.1 g (a flapper armature) to 50 kg (a brake-cylinder piston)"},
    {"valve.spring_rate", "N/m", 0.0, 1e7, "a spring of up to 10 kN/mm"},
    {"valve.spring_preload", "N", 0.0, 2e4, "a preload of up to 20 kN (a brake-cylinder return spring)"},
    {"valve.damping", "N.s/m", 0.0, 1e5, "viscous damping of up to 100 N per mm/s"},
    {"valve.friction", "N", 0.0, 1e3, "Coulomb sealing friction of up to 1 kN"},
    {"valve.friction_velocity", "m/s", 1e-7, 0.1, "a friction regularisation of 0.1 um/s to 0.1 m/s"},
    {"valve.gap", "m", 1e-5, 0.01, "a solenoid air gap of 0.01 to 10 mm"},
    {"valve.travel", "m", 1e-5, 0.05, "a stroke of 0.01 to 50 mm"},
    {"valve.lap", "m", 0.0, 0.01, "a seat overlap of 0 to 10 mm"},
    {"valve.membrane_position", "m", -0.05, 0.05, "a membrane displacement within 50 mm of its centre"},
    {"valve.membrane_volume", "m3", -0.01, 0.01, "a membrane's swept volume within 10 l"},
    {"valve.port_diameter", "m", 1e-4, 0.05, "a nozzle, orifice or seat of 0.1 to 50 mm"},
    {"valve.piston_diameter", "m", 1e-3, 0.5, "a piston, pole or brake cylinder of 1 to 500 mm"},
    {"valve.volume", "m3", 1e-7, 0.1, "a chamber of 0.1 cm3 to 100 l"},
    {"valve.cylinder_count", "1", 1.0, 16.0, "1 to 16 brake cylinders lumped per bogie"},
    {"valve.current", "A", 1e-3, 20.0, "a valve coil current of 1 mA to 20 A"},
    {"valve.table_current", "A", 0.0, 20.0, "a force table's currents of 0 to 20 A"},
    {"valve.turns", "1", 1.0, 1e5, "a coil of 1 to 100 000 turns"},
    {"valve.coil_resistance", "ohm", 1e-3, 1e4, "a coil of 1 mohm to 10 kohm"},
    {"valve.resistance_tempco", "1/K", 0.0, 0.01, "0 to 1 %/K (annealed copper 0.393 %/K, IEC 60028)"},
    {"valve.iron_length", "m", 1e-3, 1.0, "a magnetic path of 1 mm to 1 m"},
    {"valve.iron_area", "m2", 1e-7, 0.01, "an iron or gap section of 0.1 mm2 to 100 cm2"},
    {"valve.working_gaps", "1", 1.0, 2.0, "a plunger (1) or a U-core armature (2)"},
    {"valve.fringing", "1", 0.0, 5.0, "pole edges grown by 0 to 5 gaps (Roters: about 1)"},
    {"valve.parasitic_gap", "m", 0.0, 0.01, "a parasitic gap of 0 to 10 mm"},
    {"valve.leakage_permeance", "H", 0.0, 1e-5, "a leakage permeance of 0 to 10 uH"},
    {"valve.magnetic_field", "A/m", 0.0, 1e7, "a B-H curve up to 10 MA/m"},
    {"valve.flux_density", "T", 0.0, 3.0, "a B-H curve up to 3 T (iron saturates near 2 T)"},
    {"valve.drive_voltage", "V", 0.1, 1000.0, "a valve driver supply of 0.1 to 1000 V"},
    {"valve.pwm_frequency", "Hz", 1.0, 1e6, "a chopping frequency of 1 Hz to 1 MHz"},
    {"valve.coil_temperature", "K", 173.15, 523.15, "a coil at -100 to 250 degC"},
    {"valve.study_time", "s", 1e-4, 1e6, "a study of 0.1 ms to about 12 days"},
    {"valve.solver_step", "s", 1e-9, 1e-3, "an integration step of 1 ns to 1 ms"},
    {"valve.heat_capacity", "J/K", 0.01, 1e5, "a coil of 10 mJ/K to 100 kJ/K"},
    {"valve.thermal_conductance", "W/K", 1e-4, 1e3, "a coil's conductance to ambient of 0.1 mW/K to 1 kW/K"},
    {"valve.hot_spot", "K", 0.0, 100.0, "a hot spot of 0 to 100 K above the mean coil temperature"},
};

int rb_bound_count(void) { return (int)(sizeof bounds / sizeof bounds[0]); }

const rb_bound *rb_bound_at(int i) { return i >= 0 && i < rb_bound_count() ? &bounds[i] : NULL; }

const rb_bound *rb_bound_find(const char *name)
{
    for (int i = 0; name && i < rb_bound_count(); ++i)
        if (strcmp(bounds[i].name, name) == 0) return &bounds[i];
    return NULL;
}

rb_status rb_bound_check(rb_error *err, const char *name, const char *label, double value)
{
    const rb_bound *b = rb_bound_find(name);
    if (!b) return rb_fail(err, RB_EINVAL, "%s: no bound named %s (rb_bounds.c)", label, name);
    if (isfinite(value) && value >= b->min && value <= b->max) return RB_OK;
    return rb_fail(err, RB_EINVAL, "%s = %g %s: must be a finite number in [%g, %g] %s (%s)", label, value,
                   b->unit, b->min, b->max, b->unit, b->why);
}

#define CAR_BOUND(field)                                                                      \
    do {                                                                                      \
        snprintf(label, sizeof label, "car[%d].%s", i, #field);                               \
        if ((s = rb_bound_check(err, "car." #field, label, c->field))) return s;              \
    } while (0)

static rb_status car_bounds(const rb_plant_car *c, int i, rb_error *err)
{
    char label[64];
    rb_status s;
    snprintf(label, sizeof label, "car[%d].mass", i);
    if ((s = rb_bound_check(err, "car.mass", label, c->vehicle.mass))) return s;
    snprintf(label, sizeof label, "car[%d].supply_pressure", i);
    if ((s = rb_bound_check(err, "car.supply_pressure", label, c->vehicle.supply_pressure))) return s;
    snprintf(label, sizeof label, "car[%d].cylinder_area", i);
    if ((s = rb_bound_check(err, "car.cylinder_area", label, c->vehicle.brake.caliper.cylinder_area))) return s;
    CAR_BOUND(supply_volume);
    CAR_BOUND(cylinder_volume);
    CAR_BOUND(pipe_volume);
    CAR_BOUND(pilot_volume);
    CAR_BOUND(relay_volume);
    CAR_BOUND(hold_area);
    CAR_BOUND(vent_area);
    CAR_BOUND(valve_delay);
    CAR_BOUND(ep_tau);
    CAR_BOUND(ep_supply_margin);
    CAR_BOUND(ep_bleed_area);
    CAR_BOUND(relay_tau);
    CAR_BOUND(relay_sweep);
    CAR_BOUND(relay_travel);
    return RB_OK;
}

rb_status rb_plant_bounds_check(const rb_plant_params *p, rb_error *err)
{
    rb_status s;
    if (!p) return rb_fail(err, RB_EINVAL, "params = NULL: plant parameters are required");
    if (p->n_cars < 1 || p->n_cars > RB_PLANT_MAX_CARS)
        return rb_fail(err, RB_EINVAL, "n_cars = %d: must be in [1, %d]", p->n_cars, RB_PLANT_MAX_CARS);
    for (int i = 0; i < p->n_cars; ++i)
        if ((s = car_bounds(&p->car[i], i, err))) return s;
    if (p->n_cars > 1 &&
        ((s = rb_bound_check(err, "coupler.stiffness", "coupler.stiffness", p->coupler.stiffness)) ||
         (s = rb_bound_check(err, "coupler.damping", "coupler.damping", p->coupler.damping))))
        return s;
    if ((s = rb_bound_check(err, "main_reservoir_volume", "main_reservoir_volume", p->main_reservoir_volume)) ||
        (s = rb_bound_check(err, "compressor_flow", "compressor_flow", p->compressor_flow)) ||
        (s = rb_bound_check(err, "initial_speed", "initial_speed", p->initial_speed)) ||
        (s = rb_bound_check(err, "temperature", "temperature", p->temperature)) ||
        (s = rb_bound_check(err, "wall_time", "wall_time", p->wall_time)) ||
        (s = rb_bound_check(err, "initial_pressure", "initial_pressure", p->initial_pressure)) ||
        (s = rb_bound_check(err, "governor_on", "governor_on", p->governor_on)) ||
        (s = rb_bound_check(err, "governor_off", "governor_off", p->governor_off)))
        return s;
    for (int i = 0; i < p->n_conditions && i < RB_MAX_CONDITIONS; ++i) {
        char label[64];
        snprintf(label, sizeof label, "condition[%d].mu0", i);
        if ((s = rb_bound_check(err, "condition.mu0", label, p->condition[i].polach.mu0))) return s;
    }
    return RB_OK;
}

#define WSP_BOUND(field)                                                                      \
    do {                                                                                      \
        if ((s = rb_bound_check(err, "wsp." #field, "wsp." #field, w->field))) return s;      \
    } while (0)

rb_status rb_wsp_check(const rb_wsp_params *w, rb_error *err)
{
    rb_status s;
    if (!w) return rb_fail(err, RB_EINVAL, "wsp = NULL: WSP parameters are required");
    WSP_BOUND(ref_decel_max);
    WSP_BOUND(ref_accel_max);
    WSP_BOUND(speed_threshold);
    WSP_BOUND(slip_threshold);
    WSP_BOUND(decel_threshold);
    WSP_BOUND(reaccel_threshold);
    WSP_BOUND(release_fraction);
    WSP_BOUND(reapply_on);
    WSP_BOUND(reapply_off);
    WSP_BOUND(reapply_time);
    WSP_BOUND(filter_time);
    WSP_BOUND(safety_time);
    WSP_BOUND(min_speed);
    WSP_BOUND(controller);
    WSP_BOUND(setpoint_speed);
    WSP_BOUND(setpoint_slip);
    WSP_BOUND(setpoint_band);
    WSP_BOUND(lead_time);
    WSP_BOUND(ref_decel_margin);
    WSP_BOUND(setpoint_release);
    WSP_BOUND(setpoint_memory);
    WSP_BOUND(setpoint_ramp);
    WSP_BOUND(ds_speed_threshold);
    WSP_BOUND(ds_slip_threshold);
    WSP_BOUND(ds_decel_threshold);
    WSP_BOUND(ds_reaccel_threshold);
    WSP_BOUND(conditioning_mode);
    WSP_BOUND(conditioning_ratio);
    return RB_OK;
}
