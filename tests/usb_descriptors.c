/* usb_descriptors.c — print the FX2 firmware's device and high-speed
 * configuration descriptors (firmware/fx2/descriptors.c) as one upper-case
 * hex string: what the kernel shows in sysfs as `descriptors`, so that
 * tests/usb-umockdev.sh can present exactly our board to libusb. */
#include "../firmware/fx2/usb.h"

#include <stdio.h>

int main(void)
{
    for (unsigned i = 0; i < DESC_DEVICE_LEN; i++)
        printf("%02X", desc_device[i]);
    for (unsigned i = 0; i < DESC_CONFIG_LEN; i++)
        printf("%02X", desc_config_hs[i]);
    putchar('\n');
    return 0;
}
