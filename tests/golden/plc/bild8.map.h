/* Network variables of bild8.dcf, made by dcf2bin map.
 * The *_ADDR values are image addresses: offsets from the start of the complete
 * process image (input area first, then output area). The IEC 61131-3 form of
 * the map gives offsets within the area instead. */
#ifndef DCF_VARMAP_H
#define DCF_VARMAP_H

#define DCF_PI_SIZE 6u
#define DCF_IN_OFFSET 0u
#define DCF_IN_SIZE 0u
#define DCF_OUT_OFFSET 0u
#define DCF_OUT_SIZE 6u

#define DCF_IN0_IN7_ADDR 0x0000u /* UNSIGNED8 0xA4C0sub1 output IN0_IN7 */
#define DCF_IN8_IN15_ADDR 0x0001u /* UNSIGNED8 0xA4C0sub2 output IN8_IN15 */
#define DCF_IN16_IN23_ADDR 0x0002u /* UNSIGNED8 0xA4C0sub3 output IN16_IN23 */
#define DCF_AIN0_ADDR 0x0004u /* UNSIGNED16 0xA580sub3 output AIN0 */

#endif /* DCF_VARMAP_H */
