/* flexcal_sim: run the compiled glove firmware in simavr, with a scripted flex sensor
 * on A0 and the UART on a pseudo-terminal.
 *
 *   flexcal_sim FIRMWARE.elf SCRIPT [--r-fixed-ohm 47000] [--vref-v 5] [--speed 1]
 *                                   [--duration S]
 *
 * SCRIPT holds "t_s resistance_ohm" lines (blank lines and # comments allowed): the
 * sensor's resistance from that simulated time on (a staircase). "open" and "short"
 * put the pin at a rail. The resistance goes through the voltage divider of
 * flexcal/divider.py (fixed resistor from Vref to the pin, sensor to ground) into the
 * ADC as millivolts. Simulated time is paced to the wall clock (times --speed).
 * On start it prints "pty /dev/pts/N" on stdout; open that with pyserial. It runs
 * until --duration simulated seconds or until it is killed (SIGTERM ends it cleanly;
 * simavr's uart_pty thread does not stop on SIGINT in a background job).
 */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "avr_adc.h"
#include "sim_avr.h"
#include "sim_elf.h"
#include "uart_pty.h"

#define MAX_STEPS 100000

typedef struct { double t_s; double r_ohm; } step_t;   /* r < 0: short; INFINITY: open */

static step_t steps[MAX_STEPS];
static int n_steps;

static int load_script(const char *path)
{
    FILE *f = fopen(path, "r");
    char buf[256];
    int lineno = 0;
    if (!f) {
        fprintf(stderr, "flexcal_sim: %s: %s\n", path, strerror(errno));
        return -1;
    }
    while (fgets(buf, sizeof buf, f)) {
        double t;
        char val[64];
        lineno++;
        if (buf[0] == '#' || buf[strspn(buf, " \t\r\n")] == '\0')
            continue;
        if (sscanf(buf, "%lf %63s", &t, val) != 2 || n_steps >= MAX_STEPS) {
            fprintf(stderr, "flexcal_sim: %s, line %d: expected 't_s resistance_ohm'\n", path, lineno);
            fclose(f);
            return -1;
        }
        steps[n_steps].t_s = t;
        if (strcmp(val, "open") == 0)
            steps[n_steps].r_ohm = INFINITY;
        else if (strcmp(val, "short") == 0)
            steps[n_steps].r_ohm = -1.0;
        else
            steps[n_steps].r_ohm = atof(val);
        if (n_steps && t < steps[n_steps - 1].t_s) {
            fprintf(stderr, "flexcal_sim: %s, line %d: times must not decrease\n", path, lineno);
            fclose(f);
            return -1;
        }
        n_steps++;
    }
    fclose(f);
    if (!n_steps) {
        fprintf(stderr, "flexcal_sim: %s: no steps in the script\n", path);
        return -1;
    }
    return 0;
}

static double wall_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static volatile sig_atomic_t stop;

static void on_term(int sig)
{
    (void)sig;
    stop = 1;
}

int main(int argc, char **argv)
{
    double r_fixed = 47000.0, vref_v = 5.0, speed = 1.0, duration = -1.0;
    elf_firmware_t fw;
    avr_t *avr;
    uart_pty_t pty;
    avr_irq_t *adc0;
    int i, cur = -1;
    double t0;
    uint32_t last_mv = 0xFFFFFFFFu;

    if (argc < 3) {
        fprintf(stderr, "usage: flexcal_sim FIRMWARE.elf SCRIPT [--r-fixed-ohm R] [--vref-v V] [--speed X] "
                        "[--duration S]\n");
        return 2;
    }
    for (i = 3; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--r-fixed-ohm")) r_fixed = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--vref-v")) vref_v = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--speed")) speed = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--duration")) duration = atof(argv[i + 1]);
        else {
            fprintf(stderr, "flexcal_sim: unknown option %s\n", argv[i]);
            return 2;
        }
    }
    if (load_script(argv[2]))
        return 2;
    memset(&fw, 0, sizeof fw);
    if (elf_read_firmware(argv[1], &fw)) {
        fprintf(stderr, "flexcal_sim: %s: cannot read the firmware (build it with make -C firmware)\n", argv[1]);
        return 2;
    }
    avr = avr_make_mcu_by_name("atmega328p");
    if (!avr) {
        fprintf(stderr, "flexcal_sim: simavr has no atmega328p\n");
        return 2;
    }
    avr_init(avr);
    avr_load_firmware(avr, &fw);
    avr->frequency = 16000000;
    avr->vcc = avr->avcc = avr->aref = (uint32_t)(vref_v * 1000.0 + 0.5);
    avr->log = LOG_ERROR;

    uart_pty_init(avr, &pty);
    uart_pty_connect(&pty, '0');
    printf("pty %s\n", pty.port[0].slavename);
    fflush(stdout);
    adc0 = avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, ADC_IRQ_ADC0);

    signal(SIGTERM, on_term);
    t0 = wall_s();
    while (!stop) {
        double sim_s = (double)avr->cycle / avr->frequency;
        int state;
        while (cur + 1 < n_steps && steps[cur + 1].t_s <= sim_s)
            cur++;
        {
            /* The real ADC returns floor(1024 * V / Vref); simavr's model returns
             * floor(mV * 1023 / Vref_mV) from whole millivolts. Feed the millivolts that
             * make simavr return what the chip would. */
            double r = cur < 0 ? steps[0].r_ohm : steps[cur].r_ohm;
            double v = isinf(r) ? vref_v : (r < 0 ? 0.0 : vref_v * r / (r + r_fixed));
            double ref_mv = vref_v * 1000.0;
            double code = floor(1024.0 * v / vref_v);
            uint32_t mv;
            if (code > 1023.0)
                code = 1023.0;
            mv = (uint32_t)ceil(code * ref_mv / 1023.0);
            if (mv != last_mv) {
                avr_raise_irq(adc0, mv);
                last_mv = mv;
            }
        }
        for (i = 0; i < 2000; i++) {
            state = avr_run(avr);
            if (state == cpu_Done || state == cpu_Crashed)
                break;
        }
        if (state == cpu_Done || state == cpu_Crashed) {
            fprintf(stderr, "flexcal_sim: the firmware stopped (state %d)\n", state);
            return 1;
        }
        if (duration >= 0 && sim_s >= duration)
            break;
        {   /* pace simulated time to the wall clock */
            double ahead = sim_s / speed - (wall_s() - t0);
            if (ahead > 0.002)
                usleep((useconds_t)(ahead * 1e6));
        }
    }
    fflush(stdout);
    _exit(0);   /* the pty thread is left to the kernel: stopping it can hang */
}
