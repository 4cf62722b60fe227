/* Network variables of plc.dcf, made by dcf2bin map.
 * The *_ADDR values are image addresses: offsets from the start of the complete
 * process image (input area first, then output area). The IEC 61131-3 form of
 * the map gives offsets within the area instead. */
#ifndef DCF_VARMAP_H
#define DCF_VARMAP_H

#define DCF_PI_SIZE 16u
#define DCF_IN_OFFSET 0u
#define DCF_IN_SIZE 8u
#define DCF_OUT_OFFSET 8u
#define DCF_OUT_SIZE 8u

#define DCF_DIGIN_1_ADDR 0x0000u /* UNSIGNED8 0xA040sub1 input DigIn_1 */
#define DCF_DIGIN_2_ADDR 0x0001u /* UNSIGNED8 0xA040sub2 input DigIn_2 */
#define DCF_DIGIN_3_ADDR 0x0002u /* UNSIGNED8 0xA040sub3 input DigIn_3 */
#define DCF_DIGIN_4_ADDR 0x0003u /* UNSIGNED8 0xA040sub4 input DigIn_4 */
#define DCF_ANAIN_3_ADDR 0x0004u /* INTEGER16 0xA0C0sub3 input AnaIn_3 */
#define DCF_ANAIN_4_ADDR 0x0006u /* INTEGER16 0xA0C0sub4 input AnaIn_4 */
#define DCF_DIGOUT_1_ADDR 0x0008u /* UNSIGNED8 0xA4C0sub1 output DigOut_1 */
#define DCF_DIGOUT_2_ADDR 0x0009u /* UNSIGNED8 0xA4C0sub2 output DigOut_2 */
#define DCF_SETPOINT_2_ADDR 0x000Cu /* UNSIGNED32 0xA680sub2 output Setpoint_2 */

#endif /* DCF_VARMAP_H */
