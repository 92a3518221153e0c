/* descriptors.c — how the FX2 board presents itself (docs/usb-protocol.md):
 * one configuration, interface 0 vendor-specific with the bulk pair
 * 0x02 OUT / 0x86 IN, interface 1 HID with interrupt IN 0x81 and feature
 * reports 1..5.  Constant, so sdcc keeps them in code space. */
#include "usb.h"

#define LO(v) ((uint8_t)((v) & 0xFFu))
#define HI(v) ((uint8_t)((v) >> 8))

const uint8_t desc_device[] = {
    18, 1,                      /* bLength, DEVICE */
    0x00, 0x02,                 /* USB 2.0 */
    0x00, 0x00, 0x00,           /* class per interface */
    64,                         /* EP0 max packet */
    LO(PROTO_VID), HI(PROTO_VID),
    LO(PROTO_PID), HI(PROTO_PID),
    0x00, 0x01,                 /* bcdDevice 1.00 */
    1, 2, 3,                    /* manufacturer, product, serial strings */
    1,                          /* one configuration */
};

/* A high-speed capable device answers DEVICE_QUALIFIER (USB 2.0 §9.6.2). */
const uint8_t desc_qualifier[] = {
    10, 6, 0x00, 0x02, 0x00, 0x00, 0x00, 64, 1, 0,
};

/* The same configuration at both speeds but for the packet sizes: bulk 512
 * at high speed, 64 at full speed (the most USB 2.0 allows there).  HID
 * polling: 8 ms (bInterval 7 = 2^6 microframes; 8 frames at full speed). */
#define CONFIG_DESC(bulk, hid_interval)                                       \
    {                                                                         \
        9, 2, DESC_CONFIG_LEN, 0, 2, 1, 0,                                    \
        0xC0, 50,                   /* self-powered, 100 mA */                \
        9, 4, PROTO_IF_DATA, 0, 2, 0xFF, 0x00, 0x00, 0,                       \
        7, 5, PROTO_EP_OUT, 0x02, LO(bulk), HI(bulk), 0,                      \
        7, 5, PROTO_EP_IN, 0x02, LO(bulk), HI(bulk), 0,                       \
        9, 4, PROTO_IF_HID, 0, 1, 0x03, 0x00, 0x00, 0,                        \
        9, 0x21, 0x11, 0x01, 0, 1, 0x22, DESC_HID_REPORT_LEN, 0, /* HID 1.11 */ \
        7, 5, PROTO_EP_HID_IN, 0x03, PROTO_HID_REPORT, 0, hid_interval,       \
    }

const uint8_t desc_config_hs[] = CONFIG_DESC(512u, 7);
const uint8_t desc_config_fs[] = CONFIG_DESC(64u, 8);

/* Vendor-defined reports of 63 bytes after the ID (64 with it): features
 * 1 INFO, 2 RESET, 3 MODE, 4 COUNTERS, 5 LAST ERROR, and input 4 COUNTERS. */
#define FEATURE(id) 0x85, id, 0x09, id, 0xB1, 0x02   /* Report ID, Usage, Feature (Data,Var,Abs) */
const uint8_t desc_hid_report[] = {
    0x06, 0x00, 0xFF,           /* Usage Page (vendor 0xFF00) */
    0x09, 0x01,                 /* Usage 1 */
    0xA1, 0x01,                 /* Collection (Application) */
    0x15, 0x00,                 /*   Logical Minimum 0 */
    0x26, 0xFF, 0x00,           /*   Logical Maximum 255 */
    0x75, 0x08,                 /*   Report Size 8 */
    0x95, PROTO_HID_REPORT - 1, /*   Report Count 63 */
    FEATURE(PROTO_HID_INFO),
    FEATURE(PROTO_HID_RESET),
    FEATURE(PROTO_HID_MODE),
    FEATURE(PROTO_HID_COUNTERS),
    0x85, PROTO_HID_COUNTERS, 0x09, PROTO_HID_COUNTERS, 0x81, 0x02,   /* Input (Data,Var,Abs) */
    FEATURE(PROTO_HID_LASTERR),
    0xC0,                       /* End Collection */
};

/* The lengths usb.c and the HID descriptor rely on (a negative array size
 * stops the build). */
#define CHECK_LEN(a, n) typedef char a##_length_ok[sizeof a == (n) ? 1 : -1]
CHECK_LEN(desc_device, DESC_DEVICE_LEN);
CHECK_LEN(desc_qualifier, DESC_QUALIFIER_LEN);
CHECK_LEN(desc_config_hs, DESC_CONFIG_LEN);
CHECK_LEN(desc_config_fs, DESC_CONFIG_LEN);
CHECK_LEN(desc_hid_report, DESC_HID_REPORT_LEN);

/* Strings 1 and 2; 3, the serial number, is the core's serial in hex. */
const char *const desc_string_text[DESC_STRINGS] = {
    "Albatros project",
    "Albatros VP bridge (FX2LP)",
    0,
};
