/* Host unit tests of flexcal_core (gcc, no Arduino). `make -C firmware test` runs them.
 * With --table it prints "adc resistance_ohm" for every reading, for the Python suite
 * to compare with flexcal/divider.py. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../flexcal_glove/flexcal_core.h"

static int failures, checks;

#define CHECK(cond) do { checks++; if (!(cond)) { failures++; \
    fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); } } while (0)
#define CHECK_STR(got, want) do { checks++; if (strcmp((got), (want)) != 0) { failures++; \
    fprintf(stderr, "%s:%d: got \"%s\", want \"%s\"\n", __FILE__, __LINE__, (got), (want)); } } while (0)

static void test_resistance_whole_range(void)
{
    uint32_t adc;
    for (adc = 1; adc <= 1022; adc++) {
        double want = 47000.0 * (adc + 0.5) / (1024.0 - adc - 0.5);
        float got = fc_resistance_ohm(adc * 16u, 16, 47000.0f);
        CHECK(fabs(got - want) <= 2e-6 * want);
        /* and the divider's forward direction lands back in the same ADC step */
        CHECK((uint32_t)floor(1024.0 * got / (got + 47000.0)) == adc);
    }
    /* an oversampled mean between steps */
    CHECK(fabsf(fc_resistance_ohm(16u * 500u + 8u, 16, 47000.0f) - 47000.0f * 501.0f / 523.0f) < 0.05f);
}

static void test_rails(void)
{
    CHECK(fc_sensor_state_of(0, 16) == FC_SENSOR_SHORT);
    CHECK(fc_sensor_state_of(7, 16) == FC_SENSOR_SHORT);      /* mean 0.44: all but noise at 0 */
    CHECK(fc_sensor_state_of(16, 16) == FC_SENSOR_OK);
    CHECK(fc_sensor_state_of(1023u * 16u, 16) == FC_SENSOR_OPEN);
    CHECK(fc_sensor_state_of(1022u * 16u + 9u, 16) == FC_SENSOR_OPEN);
    CHECK(fc_sensor_state_of(1022u * 16u, 16) == FC_SENSOR_OK);
    CHECK(fc_sensor_state_of(0, 0) == FC_SENSOR_OPEN);
    CHECK(isnan(fc_resistance_ohm(0, 16, 47000.0f)));
    CHECK(isnan(fc_resistance_ohm(1023u * 16u, 16, 47000.0f)));
}

static void test_format(void)
{
    char b[32];
    CHECK(fc_format_float(b, sizeof b, 574.25f, 2) == 6); CHECK_STR(b, "574.25");
    fc_format_float(b, sizeof b, 60123.44f, 1); CHECK_STR(b, "60123.4");
    fc_format_float(b, sizeof b, 0.125f, 2); CHECK_STR(b, "0.13");
    fc_format_float(b, sizeof b, -1.5f, 2); CHECK_STR(b, "-1.50");
    fc_format_float(b, sizeof b, -0.004f, 2); CHECK_STR(b, "0.00");
    fc_format_float(b, sizeof b, 9.996f, 2); CHECK_STR(b, "10.00");
    fc_format_float(b, sizeof b, 7.0f, 0); CHECK_STR(b, "7");
    fc_format_float(b, sizeof b, NAN, 1); CHECK_STR(b, "nan");
    fc_format_float(b, sizeof b, INFINITY, 1); CHECK_STR(b, "nan");
    fc_format_float(b, sizeof b, 5e9f, 1); CHECK_STR(b, "nan");
    CHECK(fc_format_float(b, 5, 574.25f, 2) == 0);           /* does not fit: nothing written */
    CHECK(fc_format_u64(b, sizeof b, 18446744073709551615ull) == 20); CHECK_STR(b, "18446744073709551615");
    CHECK(fc_format_sample(b, sizeof b, 123456, 574.25f, 60123.4f, 48.21f) == 27);
    CHECK_STR(b, "123456,574.25,60123.4,48.21");
    fc_format_sample(b, sizeof b, 5, 1023.0f, NAN, NAN); CHECK_STR(b, "5,1023.00,nan,nan");
    CHECK(fc_format_sample(b, 10, 123456, 574.25f, 60123.4f, 48.21f) == 0);
}

static void test_clock_wrap(void)
{
    fc_clock c;
    fc_clock_init(&c);
    CHECK(fc_clock_extend(&c, 1000u) == 1000u);
    CHECK(fc_clock_extend(&c, 0xFFFFFFF0u) == 0xFFFFFFF0u);
    CHECK(fc_clock_extend(&c, 5u) == 0x100000005ull);
    CHECK(fc_clock_extend(&c, 25u) == 0x100000019ull);
    /* the sketch's rate check uses unsigned differences, which are wrap-safe */
    CHECK((uint32_t)(5u - 0xFFFFFFF0u) == 21u);
}

static void test_mappings(void)
{
    static const float r[] = {30000.0f, 40000.0f, 60000.0f};
    static const float a[] = {0.0f, 20.0f, 50.0f};
    fc_mapping m;
    fc_mapping_factory(&m);
    CHECK(fabsf(fc_angle_deg(&m, 31250.0f + 577.9f * 45.0f) - 45.0f) < 1e-3f);
    CHECK(isnan(fc_angle_deg(&m, NAN)));
    fc_mapping_linear(&m, 587.1f, 34400.0f);
    CHECK(fabsf(fc_angle_deg(&m, 34400.0f + 587.1f * 30.0f) - 30.0f) < 1e-3f);
    CHECK(fc_mapping_table(&m, r, a, 3) == 0);
    CHECK(fabsf(fc_angle_deg(&m, 50000.0f) - 35.0f) < 1e-4f);
    CHECK(fc_angle_deg(&m, 20000.0f) == 0.0f);                /* clamped */
    CHECK(fc_angle_deg(&m, 90000.0f) == 50.0f);
    CHECK(fc_mapping_table(&m, a, r, 3) == 0);                /* ascending is all it needs */
    {
        static const float bad[] = {30000.0f, 30000.0f, 60000.0f};
        CHECK(fc_mapping_table(&m, bad, a, 3) == -1);
        CHECK(fc_mapping_table(&m, r, a, 1) == -1);
    }
}

static fc_feed_result feed_all(fc_cmd_reader *rd, const char *s, char *out)
{
    fc_feed_result last = FC_FEED_NONE;
    for (; *s; s++) {
        fc_feed_result f = fc_cmd_feed(rd, *s);
        if (f != FC_FEED_NONE) {
            last = f;
            strcpy(out, rd->buf);
        }
    }
    return last;
}

static void test_command_reader(void)
{
    fc_cmd_reader rd;
    char line[FC_CMD_MAX + 1], longline[200];
    fc_cmd_reader_init(&rd);
    CHECK(feed_all(&rd, "rate 20\r\n", line) == FC_FEED_LINE); CHECK_STR(line, "rate 20");
    CHECK(feed_all(&rd, "\n\r\n", line) == FC_FEED_NONE);      /* empty lines are nothing */
    memset(longline, 'x', sizeof longline - 2);
    longline[sizeof longline - 2] = '\n';
    longline[sizeof longline - 1] = '\0';
    CHECK(feed_all(&rd, longline, line) == FC_FEED_OVERLONG);
    CHECK(feed_all(&rd, "info\n", line) == FC_FEED_LINE); CHECK_STR(line, "info");   /* recovers */
    CHECK(feed_all(&rd, "\xff\xfe\x01garbage\n", line) == FC_FEED_LINE);
    CHECK(rd.len == 0);
}

static void test_execute(void)
{
    fc_settings s;
    char reply[96];
    static const float r[] = {30000.0f, 90000.0f};
    static const float a[] = {0.0f, 90.0f};
    memset(&s, 0, sizeof s);
    s.rate_hz = FC_DEFAULT_RATE_HZ;
    fc_mapping_factory(&s.mapping);
    CHECK(fc_execute(&s, "rate 20", reply, sizeof reply) == 0); CHECK_STR(reply, "# ok rate_hz=20");
    CHECK(s.rate_hz == 20);
    CHECK(fc_execute(&s, "rate 0", reply, sizeof reply) == -1);
    CHECK(fc_execute(&s, "rate 201", reply, sizeof reply) == -1);
    CHECK(fc_execute(&s, "rate 20.5", reply, sizeof reply) == -1);
    CHECK(fc_execute(&s, "rate abc", reply, sizeof reply) == -1);
    CHECK(fc_execute(&s, "rate 30 40", reply, sizeof reply) == -1);
    CHECK(strncmp(reply, "# error: rate", 13) == 0);
    CHECK(s.rate_hz == 20);                                    /* a bad command changes nothing */
    CHECK(fc_execute(&s, "info", reply, sizeof reply) == 0); CHECK_STR(reply, "# info rate_hz=20 mapping=factory");
    CHECK(fc_execute(&s, "map linear 587.1 34400", reply, sizeof reply) == 0);
    CHECK_STR(reply, "# ok mapping=linear slope_ohm_per_deg=587.100 offset_ohm=34400.0");
    CHECK(s.mapping.kind == FC_MAP_LINEAR);
    CHECK(fc_execute(&s, "map linear 0 34400", reply, sizeof reply) == -1);
    CHECK(fc_execute(&s, "map linear 587.1", reply, sizeof reply) == -1);
    CHECK(fc_execute(&s, "map calibrated", reply, sizeof reply) == -1);
    CHECK(strstr(reply, "flexcal_calibration.h") != NULL);
    s.has_calibration = 1;
    fc_mapping_table(&s.calibration, r, a, 2);
    CHECK(fc_execute(&s, "map calibrated", reply, sizeof reply) == 0); CHECK_STR(reply, "# ok mapping=calibrated");
    CHECK(fc_execute(&s, "map factory", reply, sizeof reply) == 0); CHECK(s.mapping.kind == FC_MAP_FACTORY);
    CHECK(fc_execute(&s, "map sideways", reply, sizeof reply) == -1);
    CHECK(fc_execute(&s, "\xff\xfegarbage", reply, sizeof reply) == -1);
    CHECK_STR(reply, "# error: unknown command; send 'help'");
    CHECK(fc_execute(&s, "help", reply, sizeof reply) == 0);
    CHECK(fc_execute(&s, "info", reply, 10) == 0 && strlen(reply) == 9);   /* a short buffer truncates */
}

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "--table") == 0) {
        uint32_t adc;
        for (adc = 0; adc < 1024; adc++)
            printf("%u %.9g\n", (unsigned)adc, (double)fc_resistance_ohm(adc * 16u, 16, 47000.0f));
        return 0;
    }
    test_resistance_whole_range();
    test_rails();
    test_format();
    test_clock_wrap();
    test_mappings();
    test_command_reader();
    test_execute();
    printf("%d checks, %d failed\n", checks, failures);
    return failures ? 1 : 0;
}
