/* flexcal_core: see flexcal_core.h. Plain C99; no heap, no printf, no String. */
#include "flexcal_core.h"

#include <math.h>
#include <string.h>

float fc_resistance_ohm(uint32_t adc_sum, uint16_t n, float r_fixed_ohm)
{
    float mean;
    if (n == 0 || fc_sensor_state_of(adc_sum, n) != FC_SENSOR_OK)
        return NAN;
    mean = (float)adc_sum / (float)n;
    return r_fixed_ohm * (mean + 0.5f) / ((float)FC_ADC_FULL_SCALE - mean - 0.5f);
}

fc_sensor_state fc_sensor_state_of(uint32_t adc_sum, uint16_t n)
{
    /* the mean within half a step of a rail: every conversion sat there */
    if (n == 0)
        return FC_SENSOR_OPEN;
    if (2u * adc_sum <= (uint32_t)n)
        return FC_SENSOR_SHORT;
    if (2u * adc_sum >= (uint32_t)n * (2u * (FC_ADC_FULL_SCALE - 1u) - 1u))
        return FC_SENSOR_OPEN;
    return FC_SENSOR_OK;
}

void fc_mapping_factory(fc_mapping *m)
{
    memset(m, 0, sizeof *m);
    m->kind = FC_MAP_FACTORY;
    m->slope_ohm_per_deg = FC_FACTORY_SLOPE_OHM_PER_DEG;
    m->offset_ohm = FC_FACTORY_OFFSET_OHM;
}

void fc_mapping_linear(fc_mapping *m, float slope_ohm_per_deg, float offset_ohm)
{
    memset(m, 0, sizeof *m);
    m->kind = FC_MAP_LINEAR;
    m->slope_ohm_per_deg = slope_ohm_per_deg;
    m->offset_ohm = offset_ohm;
}

int fc_mapping_table(fc_mapping *m, const float *r_ohm, const float *angle_deg, uint8_t n)
{
    uint8_t i;
    if (n < 2 || n > FC_TABLE_MAX || !r_ohm || !angle_deg)
        return -1;
    for (i = 1; i < n; i++)
        if (!(r_ohm[i] > r_ohm[i - 1]))
            return -1;
    memset(m, 0, sizeof *m);
    m->kind = FC_MAP_TABLE;
    m->table_n = n;
    m->table_r_ohm = r_ohm;
    m->table_angle_deg = angle_deg;
    return 0;
}

float fc_angle_deg(const fc_mapping *m, float r_ohm)
{
    uint8_t i;
    if (isnan(r_ohm))
        return NAN;
    if (m->kind != FC_MAP_TABLE)
        return (r_ohm - m->offset_ohm) / m->slope_ohm_per_deg;
    if (r_ohm <= m->table_r_ohm[0])
        return m->table_angle_deg[0];
    for (i = 1; i < m->table_n; i++) {
        if (r_ohm <= m->table_r_ohm[i]) {
            float f = (r_ohm - m->table_r_ohm[i - 1]) / (m->table_r_ohm[i] - m->table_r_ohm[i - 1]);
            return m->table_angle_deg[i - 1] + f * (m->table_angle_deg[i] - m->table_angle_deg[i - 1]);
        }
    }
    return m->table_angle_deg[m->table_n - 1];
}

size_t fc_format_u64(char *buf, size_t n, uint64_t v)
{
    char tmp[21];
    size_t len = 0, i;
    do {
        tmp[len++] = (char)('0' + (v % 10u));
        v /= 10u;
    } while (v);
    if (len + 1 > n)
        return 0;
    for (i = 0; i < len; i++)
        buf[i] = tmp[len - 1 - i];
    buf[len] = '\0';
    return len;
}

size_t fc_format_float(char *buf, size_t n, float x, uint8_t decimals)
{
    uint32_t scale = 1, v, ip, fp;
    size_t len = 0, k;
    uint8_t d;
    if (decimals > 6)
        decimals = 6;
    for (d = 0; d < decimals; d++)
        scale *= 10u;
    /* beyond what a uint32 holds after scaling there is nothing a glove reports */
    if (isnan(x) || isinf(x) || fabsf(x) * (float)scale >= 4.0e9f) {
        if (n < 4)
            return 0;
        memcpy(buf, "nan", 4);
        return 3;
    }
    v = (uint32_t)(fabsf(x) * (float)scale + 0.5f);
    ip = v / scale;
    fp = v % scale;
    if (x < 0 && v != 0) {
        if (n < 2)
            return 0;
        buf[len++] = '-';
    }
    k = fc_format_u64(buf + len, n - len, ip);
    if (!k)
        return 0;
    len += k;
    if (decimals) {
        if (len + 1 + decimals + 1 > n)
            return 0;
        buf[len++] = '.';
        for (d = decimals; d > 0; d--) {
            buf[len + d - 1] = (char)('0' + fp % 10u);
            fp /= 10u;
        }
        len += decimals;
        buf[len] = '\0';
    }
    return len;
}

/* ",x" after the first len characters; 0 (and so on down the line) when it does not fit */
static size_t append_field(char *buf, size_t n, size_t len, float x, uint8_t decimals)
{
    size_t k;
    if (!len || len + 2 > n)
        return 0;
    buf[len++] = ',';
    k = fc_format_float(buf + len, n - len, x, decimals);
    return k ? len + k : 0;
}

size_t fc_format_sample(char *buf, size_t n, uint64_t t_ms, float adc, float r_ohm, float angle_deg)
{
    size_t len = fc_format_u64(buf, n, t_ms);
    len = append_field(buf, n, len, adc, 2);
    len = append_field(buf, n, len, r_ohm, 1);
    return append_field(buf, n, len, angle_deg, 2);
}

void fc_clock_init(fc_clock *c)
{
    c->last = 0;
    c->high = 0;
}

uint64_t fc_clock_extend(fc_clock *c, uint32_t millis_now)
{
    if (millis_now < c->last)
        c->high++;            /* millis() wrapped since the last call */
    c->last = millis_now;
    return ((uint64_t)c->high << 32) | millis_now;
}

void fc_cmd_reader_init(fc_cmd_reader *r)
{
    r->len = 0;
    r->overflow = 0;
    r->buf[0] = '\0';
}

fc_feed_result fc_cmd_feed(fc_cmd_reader *r, char c)
{
    if (c == '\r')
        return FC_FEED_NONE;
    if (c == '\n') {
        fc_feed_result res = r->overflow ? FC_FEED_OVERLONG : FC_FEED_LINE;
        r->buf[r->len] = '\0';
        if (r->overflow)
            r->len = 0;
        r->overflow = 0;
        if (res == FC_FEED_LINE && r->len == 0)
            return FC_FEED_NONE;   /* an empty line is nothing */
        r->len = 0;
        return res;
    }
    if (r->overflow)
        return FC_FEED_NONE;
    if (r->len >= FC_CMD_MAX) {
        r->overflow = 1;
        r->len = 0;
        return FC_FEED_NONE;
    }
    r->buf[r->len++] = c;
    r->buf[r->len] = '\0';
    return FC_FEED_NONE;
}

int fc_parse_float(const char *s, float *out, const char **end)
{
    float v = 0.0f, scale = 1.0f;
    int neg = 0, digits = 0;
    while (*s == ' ' || *s == '\t')
        s++;
    if (*s == '+' || *s == '-')
        neg = (*s++ == '-');
    while (*s >= '0' && *s <= '9') {
        v = v * 10.0f + (float)(*s++ - '0');
        digits++;
    }
    if (*s == '.') {
        s++;
        while (*s >= '0' && *s <= '9') {
            scale /= 10.0f;
            v += scale * (float)(*s++ - '0');
            digits++;
        }
    }
    if (!digits)
        return -1;
    if (*s && *s != ' ' && *s != '\t')
        return -1;
    *out = neg ? -v : v;
    if (end)
        *end = s;
    return 0;
}

/* Constant strings live in flash on the AVR (its 2 KB of RAM would otherwise hold every
 * message); FC_S marks them and put_c copies them out. */
#ifdef __AVR__
#include <avr/pgmspace.h>
#define FC_S(s) PSTR(s)
static size_t put_c(char *buf, size_t n, size_t at, const char *s)
{
    char c;
    while ((c = (char)pgm_read_byte(s)) != '\0' && at + 1 < n) {
        buf[at++] = c;
        s++;
    }
    if (n)
        buf[at < n ? at : n - 1] = '\0';
    return at;
}
#else
#define FC_S(s) (s)
#define put_c put
#endif

static size_t put(char *buf, size_t n, size_t at, const char *s)
{
    while (*s && at + 1 < n)
        buf[at++] = *s++;
    if (n)
        buf[at < n ? at : n - 1] = '\0';
    return at;
}

static size_t put_float(char *buf, size_t n, size_t at, float x, uint8_t decimals)
{
    char tmp[24];
    if (!fc_format_float(tmp, sizeof tmp, x, decimals))
        memcpy(tmp, "?", 2);
    return put(buf, n, at, tmp);
}

static int word_is(const char **p, const char *w)
{
    size_t k = strlen(w);
    if (strncmp(*p, w, k) == 0 && ((*p)[k] == '\0' || (*p)[k] == ' ')) {
        *p += k;
        while (**p == ' ')
            (*p)++;
        return 1;
    }
    return 0;
}

static size_t describe_mapping(const fc_settings *s, char *reply, size_t n, size_t at)
{
    switch (s->mapping.kind) {
    case FC_MAP_TABLE:
        return put_c(reply, n, at, FC_S("mapping=calibrated"));
    case FC_MAP_LINEAR:
        at = put_c(reply, n, at, FC_S("mapping=linear slope_ohm_per_deg="));
        at = put_float(reply, n, at, s->mapping.slope_ohm_per_deg, 3);
        at = put_c(reply, n, at, FC_S(" offset_ohm="));
        return put_float(reply, n, at, s->mapping.offset_ohm, 1);
    default:
        return put_c(reply, n, at, FC_S("mapping=factory"));
    }
}

int fc_execute(fc_settings *s, const char *line, char *reply, size_t n)
{
    const char *p = line;
    size_t at;
    float a, b;
    while (*p == ' ')
        p++;
    if (word_is(&p, "rate")) {
        if (fc_parse_float(p, &a, &p) || *p || a < FC_MIN_RATE_HZ || a > FC_MAX_RATE_HZ || a != (float)(uint16_t)a) {
            put_c(reply, n, 0, FC_S("# error: rate takes a whole number of hertz from 1 to 200, e.g. 'rate 50'"));
            return -1;
        }
        s->rate_hz = (uint16_t)a;
        at = put_c(reply, n, 0, FC_S("# ok rate_hz="));
        put_float(reply, n, at, a, 0);
        return 0;
    }
    if (word_is(&p, "info") && !*p) {
        at = put_c(reply, n, 0, FC_S("# info rate_hz="));
        at = put_float(reply, n, at, (float)s->rate_hz, 0);
        at = put_c(reply, n, at, FC_S(" "));
        describe_mapping(s, reply, n, at);
        return 0;
    }
    if (word_is(&p, "map")) {
        if (word_is(&p, "factory") && !*p) {
            fc_mapping_factory(&s->mapping);
        } else if (word_is(&p, "calibrated") && !*p) {
            if (!s->has_calibration) {
                put_c(reply, n, 0, FC_S("# error: no calibration compiled in; add flexcal_calibration.h and rebuild"));
                return -1;
            }
            s->mapping = s->calibration;
        } else if (word_is(&p, "linear")) {
            if (fc_parse_float(p, &a, &p) || fc_parse_float(p, &b, &p) || *p || !(a > 0.0f || a < 0.0f)) {
                put_c(reply, n, 0, FC_S("# error: write 'map linear <slope_ohm_per_deg> <offset_ohm>', slope not 0"));
                return -1;
            }
            fc_mapping_linear(&s->mapping, a, b);
        } else {
            put_c(reply, n, 0, FC_S("# error: map takes factory, calibrated or linear <slope> <offset>"));
            return -1;
        }
        at = put_c(reply, n, 0, FC_S("# ok "));
        describe_mapping(s, reply, n, at);
        return 0;
    }
    if (word_is(&p, "help") && !*p) {
        put_c(reply, n, 0, FC_S("# commands: rate <hz> | info | map factory|calibrated|linear <slope> <offset>"));
        return 0;
    }
    put_c(reply, n, 0, FC_S("# error: unknown command; send 'help'"));
    return -1;
}
