/* usb.c — the FX2 board's control endpoint: chapter 9 standard requests
 * (descriptors, configuration, interface, status, endpoint halt) and the HID
 * class requests, whose reports are the core's (fw_hid_get / fw_hid_set).
 * Polled from the main loop: SUDAV in USBIRQ says a SETUP packet waits in
 * SETUPDAT; the answer is built in EP0BUF and the status stage ends when
 * the firmware clears HSNAK (TRM chapter 2, "Endpoint Zero").  The FX2
 * handles SET_ADDRESS by itself.  Every reply fits one 64-byte EP0 packet. */
#include "usb.h"
#include "fx2regs.h"

/* bmRequestType */
#define RT_TYPE_MASK  0x60u
#define RT_STANDARD   0x00u
#define RT_CLASS      0x20u
#define RT_RECIPIENT  0x1Fu
#define RT_DEVICE     0x00u
#define RT_INTERFACE  0x01u
#define RT_ENDPOINT   0x02u

/* standard requests (USB 2.0 table 9-4) */
#define GET_STATUS        0x00u
#define CLEAR_FEATURE     0x01u
#define SET_FEATURE       0x03u
#define SET_ADDRESS       0x05u
#define GET_DESCRIPTOR    0x06u
#define GET_CONFIGURATION 0x08u
#define SET_CONFIGURATION 0x09u
#define GET_INTERFACE     0x0Au
#define SET_INTERFACE     0x0Bu
#define FEATURE_HALT      0x00u

/* descriptor types */
#define DT_DEVICE       1u
#define DT_CONFIG       2u
#define DT_STRING       3u
#define DT_QUALIFIER    6u
#define DT_OTHER_SPEED  7u
#define DT_HID          0x21u
#define DT_HID_REPORT   0x22u

/* HID class requests (HID 1.11 §7.2) */
#define HID_GET_REPORT  0x01u
#define HID_GET_IDLE    0x02u
#define HID_SET_REPORT  0x09u
#define HID_SET_IDLE    0x0Au
#define HID_INPUT       1u
#define HID_FEATURE     3u

#define EP0_SIZE    64u
#define STRING_MAX  30u   /* characters: 2 + 2·30 bytes stays under one packet */

static uint8_t configuration;     /* 0 until SET_CONFIGURATION 1 */
static uint8_t hid_idle;

uint8_t usb_configured(void) { return configuration; }

/* The IN data stage: n bytes already in EP0BUF, cut to what the host asked
 * for; a full packet shorter than what was asked ends with a ZLP. */
static void ep0_reply(uint8_t n)
{
    uint8_t want = SETUPDAT[7] ? 0xFFu : SETUPDAT[6];

    if (n > want)
        n = want;
    EP0BCH = 0;
    SYNCDELAY;
    EP0BCL = n;
    if (n == EP0_SIZE && want > EP0_SIZE) {
        while (EP0CS & bmEPBUSY)
            ;
        EP0BCH = 0;
        SYNCDELAY;
        EP0BCL = 0;
    }
}

/* Constant data (a descriptor in code space) as the reply. */
static void ep0_reply_from(const uint8_t *p, uint8_t n)
{
    uint8_t i;
    for (i = 0; i < n; i++)
        EP0BUF[i] = p[i];
    ep0_reply(n);
}

/* The OUT data stage of a control write (our HID reports: one packet);
 * returns the bytes received in EP0BUF. */
static uint8_t ep0_receive(void)
{
    EP0BCH = 0;
    SYNCDELAY;
    EP0BCL = 0;   /* arm EP0 for the data */
    SYNCDELAY;
    while (EP0CS & bmEPBUSY)
        ;
    return EP0BCL;
}

/* The control/status register of a USB-visible endpoint, 0 for others. */
static __xdata volatile uint8_t *endpoint_cs(uint8_t ep)
{
    switch (ep) {
    case 0x00:
    case 0x80:
        return &EP0CS;
    case PROTO_EP_HID_IN:
        return &EP1INCS;
    case PROTO_EP_OUT:
        return &EP2CS;
    case PROTO_EP_IN:
        return &EP6CS;
    default:
        return 0;
    }
}

static void reset_toggle(uint8_t ep)
{
    TOGCTL = (uint8_t)((ep & 0x0Fu) | ((ep & 0x80u) ? bmTOG_IO : 0u));
    TOGCTL = (uint8_t)(TOGCTL | bmTOG_RESET);
}

static void reset_data_toggles(void)
{
    reset_toggle(PROTO_EP_OUT);
    reset_toggle(PROTO_EP_IN);
    reset_toggle(PROTO_EP_HID_IN);
}

/* String descriptor n in EP0BUF, UTF-16LE from ASCII; the last one is the
 * serial number, the core's serial in hex (sdcc stores it little-endian).
 * 0 if there is no such string. */
static uint8_t string_descriptor(uint8_t n)
{
    static const char hex[] = "0123456789ABCDEF";
    const __xdata uint8_t *serial = (const __xdata uint8_t *)&fx2_core.serial;
    const char *s;
    uint8_t len, i, c;

    if (n > DESC_STRINGS)
        return 0;
    EP0BUF[1] = DT_STRING;
    if (n == 0) {   /* the language list: English (US) */
        EP0BUF[2] = 0x09;
        EP0BUF[3] = 0x04;
        return EP0BUF[0] = 4;
    }
    if (n < DESC_STRINGS) {
        s = desc_string_text[n - 1];
        for (len = 0; s[len] && len < STRING_MAX; len++)
            EP0BUF[2 + 2 * len] = (uint8_t)s[len];
    } else {   /* 8 hex digits, the most significant first */
        for (len = 0; len < 8; len++) {
            c = serial[3 - len / 2];
            EP0BUF[2 + 2 * len] = (uint8_t)hex[(len & 1) ? c & 0xFu : c >> 4];
        }
    }
    for (i = 0; i < len; i++)
        EP0BUF[3 + 2 * i] = 0;
    return EP0BUF[0] = (uint8_t)(2 + 2 * len);
}

static uint8_t get_descriptor(void)
{
    uint8_t hs = (USBCS & bmHSM) != 0, n;
    const uint8_t *cfg = hs ? desc_config_hs : desc_config_fs;

    switch (SETUPDAT[3]) {
    case DT_DEVICE:
        ep0_reply_from(desc_device, DESC_DEVICE_LEN);
        return 1;
    case DT_QUALIFIER:
        ep0_reply_from(desc_qualifier, DESC_QUALIFIER_LEN);
        return 1;
    case DT_CONFIG:
        ep0_reply_from(cfg, DESC_CONFIG_LEN);
        return 1;
    case DT_OTHER_SPEED:   /* the other speed's configuration, retyped */
        cfg = hs ? desc_config_fs : desc_config_hs;
        for (n = 0; n < DESC_CONFIG_LEN; n++)
            EP0BUF[n] = cfg[n];
        EP0BUF[1] = DT_OTHER_SPEED;
        ep0_reply(DESC_CONFIG_LEN);
        return 1;
    case DT_STRING:
        n = string_descriptor(SETUPDAT[2]);
        if (n)
            ep0_reply(n);
        return n != 0;
    case DT_HID:
        ep0_reply_from(cfg + DESC_HID_OFFSET, DESC_HID_LEN);
        return 1;
    case DT_HID_REPORT:
        ep0_reply_from(desc_hid_report, DESC_HID_REPORT_LEN);
        return 1;
    default:
        return 0;
    }
}

/* GET_STATUS, CLEAR_FEATURE and SET_FEATURE addressed to an endpoint */
static uint8_t endpoint_request(uint8_t request)
{
    __xdata volatile uint8_t *cs = endpoint_cs(SETUPDAT[4]);

    if (!cs)
        return 0;
    if (request == GET_STATUS) {
        EP0BUF[0] = *cs & bmEPSTALL;
        EP0BUF[1] = 0;
        ep0_reply(2);
        return 1;
    }
    if (SETUPDAT[2] != FEATURE_HALT)
        return 0;
    if (request == SET_FEATURE)
        *cs |= bmEPSTALL;
    else {
        *cs &= (uint8_t)~bmEPSTALL;
        reset_toggle(SETUPDAT[4]);
    }
    return 1;
}

static uint8_t standard_request(void)
{
    uint8_t request = SETUPDAT[1], recipient = SETUPDAT[0] & RT_RECIPIENT;

    if (recipient == RT_ENDPOINT &&
        (request == GET_STATUS || request == CLEAR_FEATURE || request == SET_FEATURE))
        return endpoint_request(request);
    switch (request) {
    case GET_DESCRIPTOR:
        return get_descriptor();
    case GET_CONFIGURATION:
    case GET_INTERFACE:   /* one alternate setting per interface: 0 */
        EP0BUF[0] = request == GET_CONFIGURATION ? configuration : 0;
        ep0_reply(1);
        return 1;
    case SET_CONFIGURATION:
    case SET_INTERFACE:
        if (SETUPDAT[2] > (request == SET_CONFIGURATION ? 1u : 0u))
            return 0;
        if (request == SET_CONFIGURATION)
            configuration = SETUPDAT[2];
        reset_data_toggles();
        return 1;
    case GET_STATUS:   /* device: self-powered, as the configuration says */
        EP0BUF[0] = recipient == RT_DEVICE;
        EP0BUF[1] = 0;
        ep0_reply(2);
        return 1;
    case CLEAR_FEATURE:
    case SET_FEATURE:   /* device remote wake-up: nothing to do */
    case SET_ADDRESS:
        return 1;
    default:
        return 0;
    }
}

/* HID class requests to interface 1: the core's reports, 64 bytes with the
 * ID in byte 0. */
static uint8_t hid_request(void)
{
    uint8_t id = SETUPDAT[2], kind = SETUPDAT[3], n;

    switch (SETUPDAT[1]) {
    case HID_GET_REPORT:
        if (kind != HID_FEATURE && !(kind == HID_INPUT && id == PROTO_HID_COUNTERS))
            return 0;
        EP0BUF[0] = id;
        n = fw_hid_get(&fx2_core, EP0BUF);
        if (n)
            ep0_reply(n);
        return n != 0;
    case HID_SET_REPORT:
        if (kind != HID_FEATURE)
            return 0;
        n = ep0_receive();
        return n && EP0BUF[0] == id && fw_hid_set(&fx2_core, EP0BUF, n) == 0;
    case HID_SET_IDLE:
        hid_idle = SETUPDAT[3];
        return 1;
    case HID_GET_IDLE:
        EP0BUF[0] = hid_idle;
        ep0_reply(1);
        return 1;
    default:
        return 0;
    }
}

static void setup_packet(void)
{
    uint8_t type = SETUPDAT[0] & RT_TYPE_MASK, ok = 0;

    if (type == RT_STANDARD)
        ok = standard_request();
    else if (type == RT_CLASS && (SETUPDAT[0] & RT_RECIPIENT) == RT_INTERFACE &&
             SETUPDAT[4] == PROTO_IF_HID)
        ok = hid_request();
    if (!ok)
        EP0CS |= bmEPSTALL;
    EP0CS |= bmHSNAK;   /* end the status stage (ACK, or the STALL above) */
}

void usb_init(void)
{
    uint16_t i;
    uint8_t j;

    /* Renumerate: drop off the bus, take EP0 from the boot ROM, come back
     * with our descriptors; some 50 ms off the bus (s51 cycle count), long
     * enough for the hub to notice. */
    USBCS |= bmDISCON | bmRENUM;
    for (j = 0; j < 16; j++)
        for (i = 0; i < 5000; i++)
            __asm__("nop");
    USBIRQ = 0xFF;   /* writing 1 clears a request bit */
    EPIRQ = 0xFF;
    USBCS &= (uint8_t)~bmDISCON;
}

void usb_poll(void)
{
    uint8_t irq = USBIRQ;

    if (irq & bmURES)   /* bus reset: unconfigured */
        configuration = 0;
    USBIRQ = irq & (uint8_t)~bmSUDAV;   /* clear what was seen, SUDAV below */
    if (irq & bmSUDAV) {
        USBIRQ = bmSUDAV;
        setup_packet();
    }
}
