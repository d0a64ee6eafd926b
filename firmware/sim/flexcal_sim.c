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
 * On start it prints "pty /dev/pts/N" on stdout; open that with pyserial. Like an Uno,
 * whose USB serial resets the board when the port is opened, the firmware starts only
 * once the host has opened the port (and flushed its input, as pyserial does on open;
 * at most 0.2 s after the open otherwise), so the banner is never half gone. Simulated
 * time 0 is that start. It runs until --duration simulated seconds or until it is
 * killed (SIGTERM ends it cleanly).
 */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include "avr_adc.h"
#include "avr_uart.h"
#include "sim_avr.h"
#include "sim_elf.h"

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

/* The UART's bytes to and from the pseudo-terminal's master side. The master is in
 * packet mode: each read starts with a status byte (0 for data; TIOCPKT_FLUSHREAD when
 * the host flushed its input, which tells us the host's open is complete). */
typedef struct {
    int master;
    char slavename[64];
    avr_irq_t *to_avr;
    int xon;                        /* the UART's receive FIFO has room */
    uint8_t out[8192];              /* firmware -> host, not yet taken by the pty */
    size_t n_out;
    uint8_t in[512];                /* host -> firmware, not yet given to the UART */
    size_t in_len, in_done;
} bridge_t;

static void on_uart_byte(struct avr_irq_t *irq, uint32_t value, void *param)
{
    bridge_t *b = param;
    (void)irq;
    if (b->n_out < sizeof b->out)   /* a host that stops reading loses bytes, as with a real USB serial */
        b->out[b->n_out++] = (uint8_t)value;
}

static void on_uart_xon(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq; (void)value;
    ((bridge_t *)param)->xon = 1;
}

static void on_uart_xoff(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq; (void)value;
    ((bridge_t *)param)->xon = 0;
}

static int bridge_open(bridge_t *b, avr_t *avr)
{
    struct termios tio;
    int slave, one = 1;
    uint32_t flags = 0;

    memset(b, 0, sizeof *b);
    if (openpty(&b->master, &slave, b->slavename, NULL, NULL) < 0) {
        fprintf(stderr, "flexcal_sim: cannot create a pseudo-terminal: %s\n", strerror(errno));
        return -1;
    }
    tcgetattr(slave, &tio);
    cfmakeraw(&tio);
    tcsetattr(slave, TCSANOW, &tio);
    close(slave);                   /* the master sees a hang-up until the host opens the port */
    fcntl(b->master, F_SETFL, fcntl(b->master, F_GETFL) | O_NONBLOCK);
    ioctl(b->master, TIOCPKT, &one);

    avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
    flags &= ~AVR_UART_FLAG_STDIO;  /* no copy of the output on our stdout */
    avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT), on_uart_byte, b);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XON), on_uart_xon, b);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XOFF), on_uart_xoff, b);
    b->to_avr = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
    b->xon = 1;
    return 0;
}

/* Read what the host sent, if the last read is used up; returns the status byte of a
 * control packet (0 for data or nothing). */
static int bridge_read(bridge_t *b)
{
    uint8_t buf[sizeof b->in + 1];
    ssize_t r;
    if (b->in_done < b->in_len)
        return 0;
    r = read(b->master, buf, sizeof buf);
    if (r <= 0)                     /* nothing there, or no host (EIO) */
        return 0;
    if (buf[0] != TIOCPKT_DATA)
        return buf[0];
    memcpy(b->in, buf + 1, (size_t)r - 1);
    b->in_len = (size_t)r - 1;
    b->in_done = 0;
    return 0;
}

/* Move bytes both ways; called between slices of simulated time. */
static void bridge_pump(bridge_t *b)
{
    if (b->n_out) {
        ssize_t w = write(b->master, b->out, b->n_out);
        if (w > 0) {
            memmove(b->out, b->out + w, b->n_out - (size_t)w);
            b->n_out -= (size_t)w;
        }
    }
    bridge_read(b);
    while (b->xon && b->in_done < b->in_len)
        avr_raise_irq(b->to_avr, b->in[b->in_done++]);
}

static volatile sig_atomic_t stop;

/* Wait for the host to open the port; 0 when it has (or -1 when stopped first). */
static int bridge_wait_for_host(bridge_t *b)
{
    struct pollfd pfd = { b->master, POLLIN, 0 };
    double t_open;
    while (!stop) {
        if (poll(&pfd, 1, 50) >= 0 && !(pfd.revents & POLLHUP))
            break;
    }
    if (stop)
        return -1;
    t_open = wall_s();
    while (!stop && wall_s() - t_open < 0.2) {
        if (bridge_read(b) & TIOCPKT_FLUSHREAD)
            break;
        usleep(1000);
    }
    return stop ? -1 : 0;
}

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
    bridge_t uart;
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

    if (bridge_open(&uart, avr))
        return 1;
    printf("pty %s\n", uart.slavename);
    fflush(stdout);
    adc0 = avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, ADC_IRQ_ADC0);

    signal(SIGTERM, on_term);
    if (bridge_wait_for_host(&uart))
        return 0;
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
        bridge_pump(&uart);
        if (duration >= 0 && sim_s >= duration)
            break;
        {   /* pace simulated time to the wall clock */
            double ahead = sim_s / speed - (wall_s() - t0);
            if (ahead > 0.002)
                usleep((useconds_t)(ahead * 1e6));
        }
    }
    for (i = 0; i < 100 && uart.n_out; i++) {  /* hand over the last line (up to 0.1 s) */
        bridge_pump(&uart);
        usleep(1000);
    }
    return 0;
}
