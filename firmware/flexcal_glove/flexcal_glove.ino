// flexcal glove firmware: reads the flex sensor, streams the flexcal line protocol.
//
// Protocol (115200 baud, "\r\n"): a boot banner of "#" lines, the header
// "t_ms,adc,resistance_ohm,angle_deg", then one data line per sample at RATE_HZ.
// Commands (newline-terminated): "rate <hz>", "info", "map factory|calibrated",
// "map linear <slope_ohm_per_deg> <offset_ohm>", "help". Wiring: firmware/README.md.
// The logic lives in flexcal_core.c (plain C, unit-tested on the host).

#include "flexcal_core.h"

#if defined(__has_include)
#if __has_include("flexcal_calibration.h")
#include "flexcal_calibration.h"
#define HAVE_CALIBRATION 1
#endif
#endif

static const uint8_t SENSOR_PIN = A0;
static const float R_FIXED_OHM = 47000.0f;   // fixed resistor from Vref to SENSOR_PIN
static const float VREF_V = 5.0f;            // the ADC reference (AVcc on an Uno)
static const uint8_t OVERSAMPLE = 16;         // conversions averaged per sample
static const long BAUD = 115200;

static fc_settings settings;
static fc_clock clock64;
static fc_cmd_reader reader;
static fc_sensor_state last_state = FC_SENSOR_OK;
static unsigned long next_due_us;
static char line[FC_LINE_MAX];
static char reply[96];

static void print_line(const char *s)
{
  Serial.print(s);
  Serial.print(F("\r\n"));
}

// the same for text kept in flash (F("...")): the Uno has 2 KB of RAM
static void print_line(const __FlashStringHelper *s)
{
  Serial.print(s);
  Serial.print(F("\r\n"));
}

static void banner(void)
{
  print_line(F("# flexcal-firmware " FC_VERSION " (ATmega328P)"));
  Serial.print(F("# divider: r_fixed_ohm="));
  fc_format_float(line, sizeof line, R_FIXED_OHM, 0);
  Serial.print(line);
  Serial.print(F(" vref_v="));
  fc_format_float(line, sizeof line, VREF_V, 2);
  Serial.print(line);
  print_line(F(" adc_bits=10 flex=low-side"));
  fc_execute(&settings, "info", reply, sizeof reply);
  print_line(reply);
  print_line(F("t_ms,adc,resistance_ohm,angle_deg"));
}

void setup()
{
  Serial.begin(BAUD);
  settings.rate_hz = FC_DEFAULT_RATE_HZ;
  fc_mapping_factory(&settings.mapping);
#ifdef HAVE_CALIBRATION
  if (fc_mapping_table(&settings.calibration, flexcal_cal_table_r_ohm, flexcal_cal_table_angle_deg,
                       FLEXCAL_CAL_TABLE_N) == 0) {
    settings.has_calibration = 1;
    settings.mapping = settings.calibration;
  }
#endif
  fc_clock_init(&clock64);
  fc_cmd_reader_init(&reader);
  banner();
  next_due_us = micros();
}

static void handle_commands(void)
{
  while (Serial.available() > 0) {
    fc_feed_result r = fc_cmd_feed(&reader, (char)Serial.read());
    if (r == FC_FEED_LINE) {
      fc_execute(&settings, reader.buf, reply, sizeof reply);
      print_line(reply);
    } else if (r == FC_FEED_OVERLONG) {
      print_line(F("# error: command too long (at most 48 characters); send 'help'"));
    }
  }
}

static void sample(void)
{
  uint32_t sum = 0;
  for (uint8_t i = 0; i < OVERSAMPLE; i++)
    sum += (uint32_t)analogRead(SENSOR_PIN);
  uint64_t t_ms = fc_clock_extend(&clock64, millis());
  fc_sensor_state st = fc_sensor_state_of(sum, OVERSAMPLE);
  if (st != last_state) {
    if (st == FC_SENSOR_OPEN)
      print_line(F("# warning: sensor open (ADC at the top rail): check the sensor and its wires"));
    else if (st == FC_SENSOR_SHORT)
      print_line(F("# warning: sensor shorted (ADC at 0): check for a short across the sensor"));
    else
      print_line(F("# sensor ok again"));
    last_state = st;
  }
  float r = fc_resistance_ohm(sum, OVERSAMPLE, R_FIXED_OHM);
  float adc = (float)sum / (float)OVERSAMPLE;
  if (fc_format_sample(line, sizeof line, t_ms, adc, r, fc_angle_deg(&settings.mapping, r)))
    print_line(line);
}

void loop()
{
  handle_commands();
  unsigned long period_us = 1000000UL / settings.rate_hz;
  unsigned long now = micros();
  // unsigned differences stay right across micros() wrap-around (every ~71 minutes)
  if ((long)(now - next_due_us) >= 0) {
    sample();
    next_due_us += period_us;
    if ((long)(micros() - next_due_us) > (long)period_us)  // fell behind (e.g. after a rate change): resync
      next_due_us = micros() + period_us;
  }
}
