/* SPDX-License-Identifier: MIT */
/*
 * PATU 655: crane parameters for the cranepredict C core.
 *
 * GENERATED from src/cranepredict/cranes/patu655.toml by tools/crane2header.py -- do not edit.
 * Regenerate:  python3 tools/crane2header.py   (CI checks it is current with --check)
 *
 * Use:  static const crane_params crane = CRANE_PATU655_INIT;
 * (C99 designated initializers, so the struct can live in flash). Every field of crane_params is
 * set, the side links, the pillar and the four-joint actuators included. Literals are
 * the crane file's numbers as exact doubles, rounded by CRANE_R.
 */
#ifndef CRANE_PATU655_H
#define CRANE_PATU655_H

#include "crane.h"

#ifndef CRANE_R
#define CRANE_R(x) ((crane_real)(x))
#endif

#define CRANE_PATU655_INIT { \
    .gravity = CRANE_R(9.81), \
    .lift_pivot = {.x = CRANE_R(-0.09), .y = CRANE_R(1.4261)}, \
    .lift_cylinder_base = {.x = CRANE_R(0.17), .y = CRANE_R(0.386113)}, \
    .lift_cylinder_rod = {.x = CRANE_R(0.3025), .y = CRANE_R(-0.105)}, \
    .tilt_cylinder_base = {.x = CRANE_R(1.263), .y = CRANE_R(0.206702)}, \
    .link1_pivot = {.x = CRANE_R(2.69), .y = CRANE_R(-0.006593)}, \
    .tilt_pivot = {.x = CRANE_R(2.881081), .y = CRANE_R(0.021593)}, \
    .link_pin = {.x = CRANE_R(-0.457227), .y = CRANE_R(0.0425)}, \
    .link2_end = {.x = CRANE_R(-0.475), .y = CRANE_R(0.0)}, \
    .link2_attach = {.x = CRANE_R(-0.095), .y = CRANE_R(0.240432)}, \
    .extension_mount = {.x = CRANE_R(-0.415), .y = CRANE_R(0.287)}, \
    .tip_distance = CRANE_R(2.45), \
    .extension_min = CRANE_R(0.0), \
    .extension_max = CRANE_R(1.0), \
    .lift_boom.mass = CRANE_R(143.66), \
    .lift_boom.com = {.x = CRANE_R(1.229248), .y = CRANE_R(0.055596)}, \
    .lift_boom.izz = CRANE_R(67.0537), \
    .lift_boom.ixx = CRANE_R(1.055433), \
    .lift_boom.iyy = CRANE_R(66.577004), \
    .lift_boom.ixy = CRANE_R(1.44244), \
    .outer_boom.mass = CRANE_R(141.943), \
    .outer_boom.com = {.x = CRANE_R(0.643096), .y = CRANE_R(0.247055)}, \
    .outer_boom.izz = CRANE_R(58.6619), \
    .outer_boom.ixx = CRANE_R(0.992582), \
    .outer_boom.iyy = CRANE_R(58.2081), \
    .outer_boom.ixy = CRANE_R(1.53792), \
    .extension_boom.mass = CRANE_R(15.928), \
    .extension_boom.com = {.x = CRANE_R(1.225), .y = CRANE_R(0.0)}, \
    .extension_boom.izz = CRANE_R(7.97), \
    .extension_boom.ixx = CRANE_R(0.04), \
    .extension_boom.iyy = CRANE_R(7.97), \
    .extension_boom.ixy = CRANE_R(0.0), \
    .load_mass = CRANE_R(200.0), \
    .side_link1.mass = CRANE_R(11.524), \
    .side_link1.com = {.x = CRANE_R(-0.257068), .y = CRANE_R(0.004)}, \
    .side_link1.izz = CRANE_R(0.268644), \
    .side_link1.ixx = CRANE_R(0.333066), \
    .side_link1.iyy = CRANE_R(0.081849), \
    .side_link1.ixy = CRANE_R(0.017355), \
    .side_link2.mass = CRANE_R(7.9), \
    .side_link2.com = {.x = CRANE_R(-0.212792), .y = CRANE_R(0.0)}, \
    .side_link2.izz = CRANE_R(0.216772), \
    .side_link2.ixx = CRANE_R(0.052095), \
    .side_link2.iyy = CRANE_R(0.260808), \
    .side_link2.ixy = CRANE_R(0.0), \
    .cylinder[CRANE_LIFT].bore = CRANE_R(0.1), \
    .cylinder[CRANE_LIFT].rod = CRANE_R(0.056), \
    .cylinder[CRANE_LIFT].length_retracted = CRANE_R(0.82), \
    .cylinder[CRANE_LIFT].stroke_min = CRANE_R(0.0), \
    .cylinder[CRANE_LIFT].stroke_max = CRANE_R(0.535), \
    .cylinder[CRANE_LIFT].friction.coulomb = CRANE_R(210.0), \
    .cylinder[CRANE_LIFT].friction.static_ = CRANE_R(300.0), \
    .cylinder[CRANE_LIFT].friction.viscous = CRANE_R(330.0), \
    .cylinder[CRANE_LIFT].friction.stribeck_velocity = CRANE_R(0.005), \
    .cylinder[CRANE_LIFT].friction.factor = CRANE_R(4.0), \
    .cylinder[CRANE_LIFT].hydraulics.valve = CRANE_VALVE_ORIFICE, \
    .cylinder[CRANE_LIFT].hydraulics.supply_pressure = CRANE_R(8000000.0), \
    .cylinder[CRANE_LIFT].hydraulics.tank_pressure = CRANE_R(100000.0), \
    .cylinder[CRANE_LIFT].hydraulics.relief_pressure = CRANE_R(15000000.0), \
    .cylinder[CRANE_LIFT].hydraulics.nominal_flow = CRANE_R(0.0004), \
    .cylinder[CRANE_LIFT].hydraulics.nominal_pressure_drop = CRANE_R(3500000.0), \
    .cylinder[CRANE_LIFT].hydraulics.dead_band = CRANE_R(0.0), \
    .cylinder[CRANE_LIFT].hydraulics.meter_out_flow = CRANE_R(0.0), \
    .cylinder[CRANE_LIFT].hydraulics.meter_out_pressure_drop = CRANE_R(0.0), \
    .cylinder[CRANE_LIFT].hydraulics.spool_time_constant = CRANE_R(0.03), \
    .cylinder[CRANE_LIFT].hydraulics.laminar_pressure_drop = CRANE_R(200000.0), \
    .cylinder[CRANE_LIFT].hydraulics.cavitation_pressure = CRANE_R(-90000.0), \
    .cylinder[CRANE_LIFT].hydraulics.hose_volume_a = CRANE_R(0.00019002), \
    .cylinder[CRANE_LIFT].hydraulics.hose_volume_b = CRANE_R(0.00019002), \
    .cylinder[CRANE_LIFT].hydraulics.oil_bulk_modulus = CRANE_R(1650000000.0), \
    .cylinder[CRANE_LIFT].hydraulics.hose_bulk_modulus = CRANE_R(700000000.0), \
    .cylinder[CRANE_LIFT].hydraulics.cylinder_bulk_modulus = CRANE_R(210000000000.0), \
    .cylinder[CRANE_LIFT].hydraulics.leakage = CRANE_R(0.0), \
    .cylinder[CRANE_TILT].bore = CRANE_R(0.1), \
    .cylinder[CRANE_TILT].rod = CRANE_R(0.056), \
    .cylinder[CRANE_TILT].length_retracted = CRANE_R(1.05), \
    .cylinder[CRANE_TILT].stroke_min = CRANE_R(0.0), \
    .cylinder[CRANE_TILT].stroke_max = CRANE_R(0.78), \
    .cylinder[CRANE_TILT].friction.coulomb = CRANE_R(210.0), \
    .cylinder[CRANE_TILT].friction.static_ = CRANE_R(300.0), \
    .cylinder[CRANE_TILT].friction.viscous = CRANE_R(330.0), \
    .cylinder[CRANE_TILT].friction.stribeck_velocity = CRANE_R(0.005), \
    .cylinder[CRANE_TILT].friction.factor = CRANE_R(1.0), \
    .cylinder[CRANE_TILT].hydraulics.valve = CRANE_VALVE_ORIFICE, \
    .cylinder[CRANE_TILT].hydraulics.supply_pressure = CRANE_R(8000000.0), \
    .cylinder[CRANE_TILT].hydraulics.tank_pressure = CRANE_R(100000.0), \
    .cylinder[CRANE_TILT].hydraulics.relief_pressure = CRANE_R(15000000.0), \
    .cylinder[CRANE_TILT].hydraulics.nominal_flow = CRANE_R(0.0009), \
    .cylinder[CRANE_TILT].hydraulics.nominal_pressure_drop = CRANE_R(3500000.0), \
    .cylinder[CRANE_TILT].hydraulics.dead_band = CRANE_R(0.0), \
    .cylinder[CRANE_TILT].hydraulics.meter_out_flow = CRANE_R(0.0), \
    .cylinder[CRANE_TILT].hydraulics.meter_out_pressure_drop = CRANE_R(0.0), \
    .cylinder[CRANE_TILT].hydraulics.spool_time_constant = CRANE_R(0.03), \
    .cylinder[CRANE_TILT].hydraulics.laminar_pressure_drop = CRANE_R(200000.0), \
    .cylinder[CRANE_TILT].hydraulics.cavitation_pressure = CRANE_R(-90000.0), \
    .cylinder[CRANE_TILT].hydraulics.hose_volume_a = CRANE_R(0.00019002), \
    .cylinder[CRANE_TILT].hydraulics.hose_volume_b = CRANE_R(0.00019002), \
    .cylinder[CRANE_TILT].hydraulics.oil_bulk_modulus = CRANE_R(1650000000.0), \
    .cylinder[CRANE_TILT].hydraulics.hose_bulk_modulus = CRANE_R(700000000.0), \
    .cylinder[CRANE_TILT].hydraulics.cylinder_bulk_modulus = CRANE_R(210000000000.0), \
    .cylinder[CRANE_TILT].hydraulics.leakage = CRANE_R(0.0), \
    .pillar.mass = CRANE_R(93.26), \
    .pillar.com = {.x = CRANE_R(-0.017403), .y = CRANE_R(0.577291)}, \
    .pillar.izz = CRANE_R(16.53), \
    .pillar.ixx = CRANE_R(16.358844), \
    .pillar.iyy = CRANE_R(0.612552), \
    .pillar.ixy = CRANE_R(-1.27808), \
    .slew_drive.present = 1, \
    .slew_drive.bore = CRANE_R(0.08), \
    .slew_drive.pinion_radius = CRANE_R(0.09), \
    .slew_drive.slew_min = CRANE_R(-3.316126), \
    .slew_drive.slew_max = CRANE_R(3.316126), \
    .slew_drive.friction.coulomb = CRANE_R(210.0), \
    .slew_drive.friction.static_ = CRANE_R(300.0), \
    .slew_drive.friction.viscous = CRANE_R(330.0), \
    .slew_drive.friction.stribeck_velocity = CRANE_R(0.005), \
    .slew_drive.friction.factor = CRANE_R(2.0), \
    .slew_drive.hydraulics.valve = CRANE_VALVE_ORIFICE, \
    .slew_drive.hydraulics.supply_pressure = CRANE_R(8000000.0), \
    .slew_drive.hydraulics.tank_pressure = CRANE_R(100000.0), \
    .slew_drive.hydraulics.relief_pressure = CRANE_R(15000000.0), \
    .slew_drive.hydraulics.nominal_flow = CRANE_R(0.0002), \
    .slew_drive.hydraulics.nominal_pressure_drop = CRANE_R(3500000.0), \
    .slew_drive.hydraulics.dead_band = CRANE_R(0.0), \
    .slew_drive.hydraulics.meter_out_flow = CRANE_R(0.0), \
    .slew_drive.hydraulics.meter_out_pressure_drop = CRANE_R(0.0), \
    .slew_drive.hydraulics.spool_time_constant = CRANE_R(0.03), \
    .slew_drive.hydraulics.laminar_pressure_drop = CRANE_R(200000.0), \
    .slew_drive.hydraulics.cavitation_pressure = CRANE_R(-90000.0), \
    .slew_drive.hydraulics.hose_volume_a = CRANE_R(0.00019002), \
    .slew_drive.hydraulics.hose_volume_b = CRANE_R(0.00019002), \
    .slew_drive.hydraulics.oil_bulk_modulus = CRANE_R(1650000000.0), \
    .slew_drive.hydraulics.hose_bulk_modulus = CRANE_R(700000000.0), \
    .slew_drive.hydraulics.cylinder_bulk_modulus = CRANE_R(210000000000.0), \
    .slew_drive.hydraulics.leakage = CRANE_R(0.0), \
    .extension_cylinder.present = 1, \
    .extension_cylinder.bore = CRANE_R(0.07), \
    .extension_cylinder.rod = CRANE_R(0.04), \
    .extension_cylinder.friction.coulomb = CRANE_R(210.0), \
    .extension_cylinder.friction.static_ = CRANE_R(300.0), \
    .extension_cylinder.friction.viscous = CRANE_R(330.0), \
    .extension_cylinder.friction.stribeck_velocity = CRANE_R(0.005), \
    .extension_cylinder.friction.factor = CRANE_R(1.0), \
    .extension_cylinder.hydraulics.valve = CRANE_VALVE_ORIFICE, \
    .extension_cylinder.hydraulics.supply_pressure = CRANE_R(8000000.0), \
    .extension_cylinder.hydraulics.tank_pressure = CRANE_R(100000.0), \
    .extension_cylinder.hydraulics.relief_pressure = CRANE_R(15000000.0), \
    .extension_cylinder.hydraulics.nominal_flow = CRANE_R(0.0006), \
    .extension_cylinder.hydraulics.nominal_pressure_drop = CRANE_R(3500000.0), \
    .extension_cylinder.hydraulics.dead_band = CRANE_R(0.0), \
    .extension_cylinder.hydraulics.meter_out_flow = CRANE_R(0.0), \
    .extension_cylinder.hydraulics.meter_out_pressure_drop = CRANE_R(0.0), \
    .extension_cylinder.hydraulics.spool_time_constant = CRANE_R(0.03), \
    .extension_cylinder.hydraulics.laminar_pressure_drop = CRANE_R(200000.0), \
    .extension_cylinder.hydraulics.cavitation_pressure = CRANE_R(-90000.0), \
    .extension_cylinder.hydraulics.hose_volume_a = CRANE_R(0.00038004), \
    .extension_cylinder.hydraulics.hose_volume_b = CRANE_R(0.00038004), \
    .extension_cylinder.hydraulics.oil_bulk_modulus = CRANE_R(1650000000.0), \
    .extension_cylinder.hydraulics.hose_bulk_modulus = CRANE_R(700000000.0), \
    .extension_cylinder.hydraulics.cylinder_bulk_modulus = CRANE_R(210000000000.0), \
    .extension_cylinder.hydraulics.leakage = CRANE_R(0.0), \
}

#endif
