/* flexcal_core: the glove firmware's logic in plain C (no Arduino, no heap, no printf).
 *
 * Compiles for the ATmega328P inside the sketch and on the host for unit tests
 * (firmware/tests). Units live in the names, as everywhere in flexcal: resistances in
 * ohm, angles in degrees, times in milliseconds.
 *
 * Wiring (firmware/README.md): fixed resistor from Vref to the analog pin, flex sensor
 * from the pin to ground, so
 *     adc = floor(1024 * R / (R + R_fixed)),  R = R_fixed * (adc + 0.5) / (1024 - adc - 0.5)
 * which is the convention of flexcal/divider.py.
 */
#ifndef FLEXCAL_CORE_H
#define FLEXCAL_CORE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define FC_VERSION "0.1.0"
#define FC_ADC_FULL_SCALE 1024
#define FC_DEFAULT_RATE_HZ 50
#define FC_MIN_RATE_HZ 1
#define FC_MAX_RATE_HZ 200
#define FC_CMD_MAX 48        /* longest command line accepted, without its newline */
#define FC_LINE_MAX 64       /* longest line the firmware writes */
#define FC_TABLE_MAX 32

/* the factory mapping of the reference experiment: R = 577.9 * angle + 31250 */
#define FC_FACTORY_SLOPE_OHM_PER_DEG 577.9f
#define FC_FACTORY_OFFSET_OHM 31250.0f

typedef enum { FC_MAP_FACTORY = 0, FC_MAP_LINEAR, FC_MAP_TABLE } fc_map_kind;

typedef struct {
    fc_map_kind kind;
    float slope_ohm_per_deg;          /* FACTORY, LINEAR: R = slope * angle + offset */
    float offset_ohm;
    uint8_t table_n;                  /* TABLE: resistance ascending -> angle */
    const float *table_r_ohm;
    const float *table_angle_deg;
} fc_mapping;

typedef enum { FC_SENSOR_OK = 0, FC_SENSOR_OPEN, FC_SENSOR_SHORT } fc_sensor_state;

/* Resistance (ohm) from the sum of n conversions; NaN when the mean sits at a rail. */
float fc_resistance_ohm(uint32_t adc_sum, uint16_t n, float r_fixed_ohm);
/* What the mean reading says about the sensor: open (top rail), short (bottom rail) or ok. */
fc_sensor_state fc_sensor_state_of(uint32_t adc_sum, uint16_t n);

void fc_mapping_factory(fc_mapping *m);
void fc_mapping_linear(fc_mapping *m, float slope_ohm_per_deg, float offset_ohm);
/* A lookup table, resistance strictly ascending; returns 0 on success, -1 if unusable. */
int fc_mapping_table(fc_mapping *m, const float *r_ohm, const float *angle_deg, uint8_t n);
/* Angle (deg) for a resistance; NaN in, NaN out. Tables clamp to their ends. */
float fc_angle_deg(const fc_mapping *m, float r_ohm);

/* Write x with `decimals` digits after the point (rounded half away from zero); "nan"
 * for NaN or infinity. Returns characters written (no NUL counted), or 0 if it does
 * not fit in n bytes including the NUL. */
size_t fc_format_float(char *buf, size_t n, float x, uint8_t decimals);
size_t fc_format_u64(char *buf, size_t n, uint64_t v);
/* One data line "t_ms,adc,resistance_ohm,angle_deg" (2, 1 and 2 decimals), no line end. */
size_t fc_format_sample(char *buf, size_t n, uint64_t t_ms, float adc, float r_ohm, float angle_deg);

/* millis() wraps every 2^32 ms (49.7 days); this keeps a 64-bit count across wraps. */
typedef struct { uint32_t last; uint32_t high; } fc_clock;
void fc_clock_init(fc_clock *c);
uint64_t fc_clock_extend(fc_clock *c, uint32_t millis_now);

/* Command line assembly: feed bytes; a complete line is returned once. Lines longer
 * than FC_CMD_MAX are discarded up to their newline and reported as overlong. */
typedef enum { FC_FEED_NONE = 0, FC_FEED_LINE, FC_FEED_OVERLONG } fc_feed_result;
typedef struct { char buf[FC_CMD_MAX + 1]; uint8_t len; uint8_t overflow; } fc_cmd_reader;
void fc_cmd_reader_init(fc_cmd_reader *r);
fc_feed_result fc_cmd_feed(fc_cmd_reader *r, char c);

/* The firmware's adjustable state. */
typedef struct {
    uint16_t rate_hz;
    fc_mapping mapping;
    uint8_t has_calibration;          /* a flexcal_calibration.h table was compiled in */
    fc_mapping calibration;
} fc_settings;

/* Execute one command line; writes a one-line reply (starting with "# ") into reply.
 * Commands: "rate <hz>", "info", "map factory", "map calibrated",
 * "map linear <slope_ohm_per_deg> <offset_ohm>", "help". Returns 0 if understood. */
int fc_execute(fc_settings *s, const char *line, char *reply, size_t n);

/* Parse a decimal number (optional sign, digits, point, digits); 0 on success. */
int fc_parse_float(const char *s, float *out, const char **end);

#ifdef __cplusplus
}
#endif
#endif /* FLEXCAL_CORE_H */
