/* usb.h — what the FX2 firmware's three files share: the board's core
 * (main.c), the USB descriptors (descriptors.c) and the control endpoint
 * (usb.c).  docs/usb-protocol.md describes the device they present. */
#ifndef ALBATROS_FX2_USB_H
#define ALBATROS_FX2_USB_H

#include "../core.h"

#include <stdint.h>

/* main.c: the portable core, in external RAM */
extern __xdata fw_core fx2_core;

/* descriptors.c */
#define DESC_CONFIG_LEN     57u   /* configuration, 2 interfaces, HID, 3 endpoints */
#define DESC_HID_OFFSET     41u   /* the HID class descriptor inside it */
#define DESC_HID_LEN        9u
#define DESC_HID_REPORT_LEN 53u
#define DESC_STRINGS        3u    /* string indices 1..3; 3 is the serial number */
#define DESC_DEVICE_LEN     18u
#define DESC_QUALIFIER_LEN  10u
extern const uint8_t desc_device[];       /* lengths checked in descriptors.c */
extern const uint8_t desc_qualifier[];
extern const uint8_t desc_config_hs[];
extern const uint8_t desc_config_fs[];
extern const uint8_t desc_hid_report[];
extern const char *const desc_string_text[DESC_STRINGS];   /* ASCII; [2] unused */

/* usb.c: renumerate with our descriptors, then serve EP0 from the main loop
 * (everything is polled: no interrupt handler touches the core). */
void usb_init(void);
void usb_poll(void);
uint8_t usb_configured(void);

#endif
